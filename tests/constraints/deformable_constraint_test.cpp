// The three deformable couplings: g against the reference formulas and J
// against central differences of g over every DoF they touch, with rotated
// actor transforms, displaced nodes and a rotated rigid body.
#include "constraint_test_util.h"

using namespace superdex;
using namespace superdex::test;

namespace {
DeformableActor* MakeBlock(Scene& scene, Real3 const& position, Quat const& rotation, real jitter) {
  TetMesh mesh;
  Error error;
  REQUIRE(MakeTetBox(Real3::Zero(), Real3(0.2, 0.1, 0.1), {2, 1, 1}, mesh, error));
  DeformableActorParams p;
  p.nodes = mesh.nodes;
  p.tetrahedra = mesh.tetrahedra;
  p.position = position;
  p.rotation = rotation;
  for (std::size_t i = 0; i < p.nodes.size(); ++i)
    p.initialDisplacements.push_back(jitter * Real3(std::sin(3.0 * i), std::cos(5.0 * i), std::sin(7.0 * i)));
  DeformableActor* actor = scene.CreateDeformableActor(p, error);
  REQUIRE(actor);
  return actor;
}


}  // namespace

TEST_CASE("deformable coupling Jacobians match central differences", "[constraints][deformable]") {
  auto scene = MakeScene();
  Quat const rotA(Eigen::AngleAxis<real>(0.7, Real3(1, 2, -1).normalized()));
  Quat const rotB(Eigen::AngleAxis<real>(2.5, Real3(0, 1, 1).normalized()));
  DeformableActor* a = MakeBlock(*scene, Real3(0.1, 0.2, 0.3), rotA, 0.01);
  DeformableActor* b = MakeBlock(*scene, Real3(-0.4, 0.1, 0), rotB, 0.02);
  RigidActorParams rp;
  rp.position = Real3(0.3, -0.2, 0.1);
  rp.rotation = Quat(Eigen::AngleAxis<real>(3.0, Real3(1, 0, 1).normalized()));
  RigidActor* rigid = MakeRigid(*scene, rp);
  Error error;

  SECTION("DeformableNodePosition: g = T(X + u) - p") {
    DeformableNodePositionConstraintParams p;  // the reference page's example
    p.actor = a->GetHandle();
    p.nodeIndex = 4;
    p.position = Real3{0_r, 1_r, 0_r};
    p.stiffness = 1e6_r;
    Constraint* c = scene->CreateDeformableNodePositionConstraint(p, error);
    REQUIRE(c);
    REQUIRE(c->GetNumDofs() == 3);
    Real3 const expected = Real3(0.1, 0.2, 0.3) +
                           rotA * (a->GetNodeReferencePosition(4) + a->GetNodeDisplacement(4)) - p.position;
    REQUIRE((Deviation(*c) - expected).norm() <= 1e-14);
    CheckJacobian(*scene, *c);
    REQUIRE(!c->HasCurvature());  // g linear in the displacements
    CheckCurvature(*c, false);
    REQUIRE(c->SetTargetPosition(Real3(1, 2, 3), error));
  }
  SECTION("DeformableNodeToDeformableNode: g = T_A(X_A + u_A) - T_B(X_B + u_B)") {
    DeformableNodeToDeformableNodeConstraintParams p;
    p.actorA = a->GetHandle();
    p.actorB = b->GetHandle();
    p.nodeIndexA = 2;
    p.nodeIndexB = 9;
    p.stiffness = 1e4;
    Constraint* c = scene->CreateDeformableNodeToDeformableNodeConstraint(p, error);
    REQUIRE(c);
    REQUIRE(c->GetNumDofs() == 6);
    REQUIRE((Deviation(*c) - (a->GetNodePosition(2) - b->GetNodePosition(9))).norm() <= 1e-14);
    CheckJacobian(*scene, *c);
    REQUIRE(!c->HasCurvature());  // g linear in the displacements
    CheckCurvature(*c, false);
  }
  SECTION("DeformableNodeToRigid: g = T_R(r) - T_D(X + u)") {
    DeformableNodeToRigidConstraintParams p;
    p.deformableActor = b->GetHandle();
    p.rigidActor = rigid->GetHandle();
    p.deformableNodeIndex = 7;
    p.fixToDeformablePos = false;
    p.localPos = Real3(0.2, -0.1, 0.3);
    p.stiffness = 1e4;
    Constraint* c = scene->CreateDeformableNodeToRigidConstraint(p, error);
    REQUIRE(c);
    REQUIRE(c->GetNumDofs() == 9);
    REQUIRE(c->GetActor(0) == b);
    REQUIRE(c->GetActor(1) == rigid);
    REQUIRE((Deviation(*c) - (rigid->TransformPoint(p.localPos) - b->GetNodePosition(7))).norm() <= 1e-14);
    CheckJacobian(*scene, *c);
    CheckCurvature(*c, true);
    // with fixToDeformablePos the pivot is chosen so that g starts at zero
    p.fixToDeformablePos = true;
    Constraint* fixed = scene->CreateDeformableNodeToRigidConstraint(p, error);
    REQUIRE(fixed);
    REQUIRE(Deviation(*fixed).norm() <= 1e-14);
  }
}

TEST_CASE("rod couplings: deformable types on rod nodes and RodElementRotationToRigid, J against central "
          "differences",
          "[constraints][deformable][rod][derivatives]") {
  // a near-straight rod (kinks of ~1e-3 rad) and a strongly bent one (a helix
  // turning 0.9 rad per element), displaced and twisted off their reference
  // frames; a rotated rigid body; rotation targets up to 3.0 rad away (J_l⁻¹
  // near π)
  bool const bent = GENERATE(false, true);
  real const targetAngle = GENERATE(0.0, 1.2, 3.0);
  CAPTURE(bent, targetAngle);
  auto scene = MakeScene();
  RodActorParams rp;
  for (int i = 0; i < 6; ++i)
    rp.nodes.push_back(bent ? Real3(0.2 * std::cos(0.9 * i), 0.2 * std::sin(0.9 * i), 0.08 * i)
                            : Real3(0.15 * i, 1e-4 * std::sin(3.0 * i), 1e-4 * std::cos(5.0 * i)));
  rp.materialDirector = Real3(0, 0.3, 1);
  Error error;
  RodActor* rod = scene->CreateRodActor(rp, error);
  INFO(error.ToString());
  REQUIRE(rod);
  DeformableActor* block = MakeBlock(*scene, Real3(-0.4, 0.1, 0), Quat(Eigen::AngleAxis<real>(0.5, Real3::UnitY())), 0.02);
  RigidActorParams bodyParams;
  bodyParams.position = Real3(0.3, -0.2, 0.1);
  bodyParams.rotation = Quat(Eigen::AngleAxis<real>(2.0, Real3(1, 0, 1).normalized()));
  RigidActor* rigid = MakeRigid(*scene, bodyParams);
  // move the rod off its reference frames (they stay where they are: a stage)
  DynamicArray<real> offset(scene->GetNumDofs(), 0);
  for (int k = 0; k < rod->GetNumDofs(); ++k)
    offset[rod->GetDofOffset() + k] = (k % 4 == 3 ? 0.3 : 0.01) * std::sin(1.7 * k + 0.3);
  ActorTestAccess::SaveIterate(*rod);
  ActorTestAccess::ApplyIncrementFromSaved(*rod, offset, 1);

  SECTION("RodElementRotationToRigid: g = Log((R_R R̂ R₀)⁻¹ R_e R₀)") {
    int const element = 2;
    RodElementRotationToRigidConstraintParams p;
    p.rigidActor = rigid->GetHandle();
    p.rodActor = rod->GetHandle();
    p.elementIndex = element;
    p.jointFrame = Quat(Eigen::AngleAxis<real>(0.8, Real3(0.2, 1, -0.3).normalized()));
    p.stiffness = 1e3;
    Constraint* c = scene->CreateRodElementRotationToRigidConstraint(p, error);
    INFO(error.ToString());
    REQUIRE(c);
    REQUIRE(c->GetDimension() == 3);
    REQUIRE(c->GetNumDofs() == 11);
    REQUIRE(c->GetActor(0) == rigid);
    REQUIRE(c->GetActor(1) == rod);
    // the rigid body's rotation DoFs, then the element's nodes' 4 DoFs each
    Span<int const> const rigidDofs = c->GetDofIndicesForActor(0), rodDofs = c->GetDofIndicesForActor(1);
    REQUIRE(DynamicArray<int>(rigidDofs.begin(), rigidDofs.end()) ==
            DynamicArray<int>{rigid->GetDofOffset() + 3, rigid->GetDofOffset() + 4, rigid->GetDofOffset() + 5});
    REQUIRE(rodDofs.size() == 8);
    for (int k = 0; k < 8; ++k) REQUIRE(rodDofs[k] == rod->GetDofOffset() + 4 * element + k);
    // the target starts at the creation-time relative rotation: g = 0
    REQUIRE(Deviation(*c).norm() <= 1e-12);
    // a target turned by targetAngle about an oblique axis (in R₀'s frame the
    // deviation is then that rotation)
    auto* typed = static_cast<RodElementRotationToRigidConstraint*>(c);
    Quat const frameInBody = rigid->GetRotation().conjugate() * p.jointFrame;
    Quat const turn(Eigen::AngleAxis<real>(targetAngle, Real3(1, -2, 0.5).normalized()));
    Quat const target = typed->GetTargetRotation() * frameInBody * turn * frameInBody.conjugate();
    REQUIRE(c->SetTargetRotation(target, error));
    // reference value through Eigen's AngleAxis
    Real33 const left = (rigid->GetRotation() * target * frameInBody).toRotationMatrix();
    Real33 const right = rod->GetMaterialFrame(element) * frameInBody.toRotationMatrix();
    Eigen::AngleAxis<real> const expected(Real33(left.transpose() * right));
    REQUIRE((Deviation(*c) - expected.angle() * expected.axis()).norm() <= 1e-12);
    REQUIRE(std::abs(Deviation(*c).norm() - targetAngle) <= 1e-12);
    // θₑ₊₁ (column 3 + 7) is listed but does not act
    CheckJacobian(*scene, *c, {10});
    CheckCurvature(*c, true);
  }
  SECTION("DeformableNodePosition, DeformableNodeToDeformableNode and DeformableNodeToRigid on rod nodes") {
    DeformableNodePositionConstraintParams pin;
    pin.actor = rod->GetHandle();
    pin.nodeIndex = 3;
    pin.position = Real3(1, 2, 3);
    pin.stiffness = 1e4;
    Constraint* c = scene->CreateDeformableNodePositionConstraint(pin, error);
    REQUIRE(c);
    Span<int const> const pinDofs = c->GetDofIndicesForActor(0);
    REQUIRE(DynamicArray<int>(pinDofs.begin(), pinDofs.end()) ==
            DynamicArray<int>{rod->GetDofOffset() + 12, rod->GetDofOffset() + 13, rod->GetDofOffset() + 14});
    REQUIRE((Deviation(*c) - (rod->GetNodePosition(3) - pin.position)).norm() <= 1e-14);
    CheckJacobian(*scene, *c);
    REQUIRE(!c->HasCurvature());  // g linear in the displacements
    CheckCurvature(*c, false);

    DeformableNodeToDeformableNodeConstraintParams link;
    link.actorA = rod->GetHandle();
    link.actorB = block->GetHandle();
    link.nodeIndexA = 5;
    link.nodeIndexB = 4;
    link.stiffness = 1e4;
    c = scene->CreateDeformableNodeToDeformableNodeConstraint(link, error);
    REQUIRE(c);
    REQUIRE((Deviation(*c) - (rod->GetNodePosition(5) - block->GetNodePosition(4))).norm() <= 1e-14);
    CheckJacobian(*scene, *c);
    REQUIRE(!c->HasCurvature());  // g linear in the displacements
    CheckCurvature(*c, false);

    DeformableNodeToRigidConstraintParams hang;
    hang.deformableActor = rod->GetHandle();
    hang.rigidActor = rigid->GetHandle();
    hang.deformableNodeIndex = 1;
    hang.fixToDeformablePos = false;
    hang.localPos = Real3(0.2, -0.1, 0.3);
    hang.stiffness = 1e4;
    c = scene->CreateDeformableNodeToRigidConstraint(hang, error);
    REQUIRE(c);
    REQUIRE((Deviation(*c) - (rigid->TransformPoint(hang.localPos) - rod->GetNodePosition(1))).norm() <= 1e-14);
    CheckJacobian(*scene, *c);
    CheckCurvature(*c, true);
  }
  SECTION("bad input: wrong actor kinds, element out of range") {
    RodElementRotationToRigidConstraintParams p;
    p.rigidActor = rigid->GetHandle();
    p.rodActor = block->GetHandle();
    p.stiffness = 1;
    REQUIRE_FALSE(scene->CreateRodElementRotationToRigidConstraint(p, error));
    REQUIRE(error.GetCode() == ErrorCode::InvalidHandle);
    REQUIRE_THAT(error.GetMessage(), Catch::Contains("rodActor") && Catch::Contains("Deformable"));
    p.rodActor = rod->GetHandle();
    p.elementIndex = 5;
    REQUIRE_FALSE(scene->CreateRodElementRotationToRigidConstraint(p, error));
    REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
    REQUIRE_THAT(error.GetMessage(), Catch::Contains("elementIndex") && Catch::Contains("got 5"));
    p.elementIndex = 4;
    p.rigidActor = rod->GetHandle();
    REQUIRE_FALSE(scene->CreateRodElementRotationToRigidConstraint(p, error));
    REQUIRE_THAT(error.GetMessage(), Catch::Contains("rigidActor") && Catch::Contains("Rod"));
    REQUIRE(scene->GetNumConstraints() == 0);
  }
}

TEST_CASE("type-specific methods on the deformable couplings", "[constraints][deformable]") {
  auto scene = MakeScene();
  DeformableActor* a = MakeBlock(*scene, Real3::Zero(), Quat::Identity(), 0);
  DeformableActor* b = MakeBlock(*scene, Real3(1, 0, 0), Quat::Identity(), 0);
  RigidActor* rigid = MakeRigid(*scene, {});
  Error error;
  DeformableNodePositionConstraintParams pin;
  pin.actor = a->GetHandle();
  DeformableNodeToDeformableNodeConstraintParams spring;
  spring.actorA = a->GetHandle();
  spring.actorB = b->GetHandle();
  DeformableNodeToRigidConstraintParams attach;
  attach.deformableActor = b->GetHandle();
  attach.rigidActor = rigid->GetHandle();
  Constraint* constraints[] = {scene->CreateDeformableNodePositionConstraint(pin, error),
                               scene->CreateDeformableNodeToDeformableNodeConstraint(spring, error),
                               scene->CreateDeformableNodeToRigidConstraint(attach, error)};
  for (Constraint* c : constraints) {
    REQUIRE(c);
    CAPTURE(ToString(c->GetType()));
    VectorX const before = Deviation(*c);
    bool const hasTarget = c->GetType() == ConstraintType::DeformableNodePosition;
    error.Clear();
    REQUIRE(c->SetTargetPosition(Real3(0, 2, 0), error) == hasTarget);
    REQUIRE(c->UpdateOldTarget(error) == hasTarget);
    if (!hasTarget) {
      REQUIRE(error.GetCode() == ErrorCode::NotSupported);
      REQUIRE(Deviation(*c) == before);
    } else {
      REQUIRE(Deviation(*c) != before);
    }
    for (auto call : {+[](Constraint* k, Error& e) { return k->SetTargetRotation(Quat::Identity(), e); },
                      +[](Constraint* k, Error& e) { return k->SetTargetDof(0.0, e); },
                      +[](Constraint* k, Error& e) { return !k->GetLimitMinValues(e).empty(); }}) {
      error.Clear();
      REQUIRE_FALSE(call(c, error));
      REQUIRE(error.GetCode() == ErrorCode::NotSupported);
    }
  }
  // a node-to-node spring needs two different actors
  spring.actorB = a->GetHandle();
  error.Clear();
  REQUIRE_FALSE(scene->CreateDeformableNodeToDeformableNodeConstraint(spring, error));
  REQUIRE(error.GetMessage().find("actorB") != std::string::npos);
  // a rigid handle where a deformable one is expected
  pin.actor = rigid->GetHandle();
  error.Clear();
  REQUIRE_FALSE(scene->CreateDeformableNodePositionConstraint(pin, error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidHandle);
  REQUIRE(scene->GetNumConstraints() == 3);
}

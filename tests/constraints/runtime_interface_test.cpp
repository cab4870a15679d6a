// The uniform runtime interface on the two types of the foundation:
// introspection, GetForce's states, limits on non-range types.
#include "test_support.h"

using namespace superdex;
using namespace superdex::test;

TEST_CASE("introspection reports actors and global DoF indices", "[constraints][interface]") {
  auto scene = MakeScene();
  RigidActor* extra = MakeRigid(*scene, {});
  RigidActor* a = MakeRigid(*scene, {});
  RigidActorParams pb;
  pb.position = Real3(1, 0, 0);
  RigidActor* b = MakeRigid(*scene, pb);
  Error error;
  RigidSphericalJointConstraintParams jp;
  jp.actorA = a->GetHandle();
  jp.actorB = b->GetHandle();
  Constraint* joint = scene->CreateRigidSphericalJointConstraint(jp, error);
  RigidPivotPositionConstraintParams pp;
  pp.actor = b->GetHandle();
  Constraint* pin = scene->CreateRigidPivotPositionConstraint(pp, error);
  REQUIRE(joint);
  REQUIRE(pin);

  REQUIRE(joint->GetType() == ConstraintType::RigidSphericalJoint);
  REQUIRE(joint->GetNumActors() == 2);
  REQUIRE(joint->GetActor(0) == a);
  REQUIRE(joint->GetActor(1) == b);
  REQUIRE(joint->GetActor(2) == nullptr);
  REQUIRE(joint->GetActor(-1) == nullptr);
  REQUIRE(joint->GetDimension() == 3);
  REQUIRE(joint->GetNumDofs() == 12);
  REQUIRE(pin->GetNumActors() == 1);
  REQUIRE(pin->GetNumDofs() == 6);
  REQUIRE(pin->GetDofIndicesForActor(1).empty());

  auto indices = [](Constraint* c, int i) {
    Span<int const> s = c->GetDofIndicesForActor(i);
    return DynamicArray<int>(s.begin(), s.end());
  };
  REQUIRE(indices(joint, 0) == DynamicArray<int>{6, 7, 8, 9, 10, 11});
  REQUIRE(indices(joint, 1) == DynamicArray<int>{12, 13, 14, 15, 16, 17});
  REQUIRE(indices(pin, 0) == DynamicArray<int>{12, 13, 14, 15, 16, 17});

  // destroying an actor created earlier renumbers the DoFs
  REQUIRE(scene->DestroyActor(extra->GetHandle(), error));
  REQUIRE(indices(joint, 0) == DynamicArray<int>{0, 1, 2, 3, 4, 5});
  REQUIRE(indices(pin, 0) == DynamicArray<int>{6, 7, 8, 9, 10, 11});

  // ForEachConstraint visits both, GetConstraint resolves handles
  int count = 0;
  scene->ForEachConstraint([&](Constraint&) { ++count; });
  REQUIRE(count == 2);
  REQUIRE(scene->GetConstraint(joint->GetHandle()) == joint);
  REQUIRE(scene->DestroyConstraint(joint, error));
  REQUIRE(scene->GetNumConstraints() == 1);
  REQUIRE_FALSE(scene->DestroyConstraint(joint, error));  // no longer live
  REQUIRE(error.GetCode() == ErrorCode::InvalidHandle);
}

TEST_CASE("GetForce needs a registered query and a completed step", "[constraints][interface]") {
  auto scene = MakeScene();
  RigidActor* body = MakeRigid(*scene, {});
  RigidPivotPositionConstraintParams pp;
  pp.actor = body->GetHandle();
  pp.stiffness = 1e4;
  Error error;
  Constraint* pin = scene->CreateRigidPivotPositionConstraint(pp, error);
  REQUIRE(pin);
  REQUIRE(pin->IsQuerySupported(QueryType::ConstraintForce));

  REQUIRE(pin->GetForce(error).empty());
  REQUIRE(error.GetCode() == ErrorCode::InvalidState);
  REQUIRE(error.GetMessage().find("RegisterQuery") != std::string::npos);

  error.Clear();
  REQUIRE(pin->RegisterQuery(QueryType::ConstraintForce, error));
  REQUIRE(pin->GetForce(error).empty());
  REQUIRE(error.GetCode() == ErrorCode::InvalidState);

  // at rest under gravity the pivot carries the weight: force = −rᶜ = +m g ŷ
  StepOk(*scene, 1e-2, 200);
  error.Clear();
  Span<real const> force = pin->GetForce(error);
  REQUIRE_FALSE(error);
  REQUIRE(force.size() == 6);
  CAPTURE(force[0], force[1], force[2]);
  REQUIRE(Near(force[1], 9.81 * body->GetMass(), 1e-6));
  REQUIRE(std::abs(force[0]) < 1e-9);
}

TEST_CASE("limits do not apply to bilateral types", "[constraints][interface]") {
  auto scene = MakeScene();
  RigidActor* body = MakeRigid(*scene, {});
  RigidPivotPositionConstraintParams pp;
  pp.actor = body->GetHandle();
  Error error;
  Constraint* pin = scene->CreateRigidPivotPositionConstraint(pp, error);
  REQUIRE(pin);
  REQUIRE_FALSE(pin->IsRange());
  REQUIRE(pin->GetLimitMinValues(error).empty());
  REQUIRE(error.GetCode() == ErrorCode::NotSupported);
  REQUIRE(error.GetMessage().find("GetLimitMinValues does not apply to a RigidPivotPosition") !=
          std::string::npos);
  error.Clear();
  REQUIRE(pin->GetLimitMaxValues(error).empty());
  REQUIRE(error.GetCode() == ErrorCode::NotSupported);
  error.Clear();
  REQUIRE_FALSE(pin->SetTargetRotation(Quat::Identity(), error));
  REQUIRE(error.GetCode() == ErrorCode::NotSupported);
  error.Clear();
  REQUIRE_FALSE(pin->SetTargetDof(1.0, error));
  REQUIRE(error.GetCode() == ErrorCode::NotSupported);
  // the position target applies, and is validated
  error.Clear();
  REQUIRE_FALSE(pin->SetTargetPosition(Real3(0, std::nan(""), 0), error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
  error.Clear();
  REQUIRE(pin->SetTargetPosition(Real3(0, 1, 0), error));
  REQUIRE(ToReal3(pin->GetDeviation()).isApprox(Real3(0, -1, 0)));
}

TEST_CASE("a spherical joint's forces on its two bodies are equal and opposite",
          "[constraints][interface]") {
  auto scene = MakeScene();
  RigidActorParams pa;
  pa.inertia = Real3(0.1, 0.2, 0.3);
  RigidActor* a = MakeRigid(*scene, pa);
  RigidActorParams pb = pa;
  pb.mass = 2;
  pb.position = Real3(0.6, -0.8, 0.1);
  RigidActor* b = MakeRigid(*scene, pb);
  Error error;
  RigidPivotPositionConstraintParams pin;
  pin.actor = a->GetHandle();
  pin.localPos = Real3(-0.3, 0, 0);
  pin.position = a->TransformPoint(pin.localPos);
  pin.stiffness = 1e6;
  REQUIRE(scene->CreateRigidPivotPositionConstraint(pin, error));
  RigidSphericalJointConstraintParams jp;
  jp.actorA = a->GetHandle();
  jp.actorB = b->GetHandle();
  jp.localPosA = Real3(0.3, 0, 0);
  jp.localPosB = b->GetRotation().conjugate() * (a->TransformPoint(jp.localPosA) - b->GetPosition());
  jp.stiffness = 1e6;
  jp.damping = 10;
  Constraint* joint = scene->CreateRigidSphericalJointConstraint(jp, error);
  REQUIRE(joint);
  REQUIRE(joint->RegisterQuery(QueryType::ConstraintForce, error));
  StepOk(*scene, 1e-3, 50);  // swinging: the joint carries a changing load
  Span<real const> f = joint->GetForce(error);
  REQUIRE(f.size() == 12);
  Real3 const onA(f[0], f[1], f[2]), onB(f[6], f[7], f[8]);
  CAPTURE(onA.transpose(), onB.transpose());
  REQUIRE(onB.norm() > 1);
  REQUIRE((onA + onB).norm() <= 1e-12 * onB.norm());
  // each torque is the force's moment about that body's centre of mass
  Real3 const armA = a->GetRotation() * jp.localPosA, armB = b->GetRotation() * jp.localPosB;
  REQUIRE((Real3(f[3], f[4], f[5]) - armA.cross(onA)).norm() <= 1e-12 * onB.norm());
  REQUIRE((Real3(f[9], f[10], f[11]) - armB.cross(onB)).norm() <= 1e-12 * onB.norm());
}

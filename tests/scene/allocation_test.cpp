// Hot paths allocate nothing: once the pattern is built and the solver has
// analyzed it, a whole step (snapshot, Newton iterations, assembly fill,
// factorization, solve, line search, commit) makes no heap allocation from
// SuperDex's own code (malloc or operator new; allocations inside CHOLMOD,
// libgomp and OpenBLAS are theirs — docs/linear_solvers.md).
#include "contact/contact_scenes.h"
#include "test_scenes.h"

#include "allocation_recorder.h"

using namespace superdex;
using namespace superdex::test;

namespace {

/// Steps `scene` `steps` times by `dt` and requires that every step succeed,
/// that Newton iterate at least once per step, and that SuperDex allocate
/// nothing while it does (the caller has taken the first steps that build
/// the pattern, the analysis and the snapshots).
void RequireStepsAllocateNothing(Scene& scene, real dt, int steps) {
  Error error;
  int newtonIterations = 0;
  int const during = CountAllocations([&] {
                       for (int i = 0; i < steps; ++i) {
                         bool const ok = scene.Step(dt, error);
                         newtonIterations += scene.GetStats().newtonIterations;
                         if (!ok) break;
                       }
                     }).superdex;
  INFO(error.ToString());
  REQUIRE_FALSE(error);
  REQUIRE(newtonIterations >= steps);
  REQUIRE(during == 0);
}

}  // namespace

TEST_CASE("steps after the first allocate nothing", "[scene][allocation]") {
  LinearSolverType const solver = GENERATE(LinearSolverType::Cholmod, LinearSolverType::Dense);
  CAPTURE(ToString(solver));
  SceneParams params;
  params.linearSolver = solver;
  params.integrator = IntegratorType::Bdf2;
  Chain chain = MakeChain(12, params);
  Error error;
  Constraint* first = nullptr;
  chain.scene->ForEachConstraint([&](Constraint& c) {
    if (!first) first = &c;
  });
  REQUIRE(first->RegisterQuery(QueryType::ConstraintForce, error));
  StepOk(*chain.scene, 1e-3, 2);  // builds pattern, analysis, snapshots
  RequireStepsAllocateNothing(*chain.scene, 1e-3, 20);
}

TEST_CASE("every constraint Hessian allocates nothing, the clamped geometric stiffness included",
          "[scene][allocation][geometric-stiffness]") {
  // HessianProjection::Always sends every iteration through the projected
  // path: the geometric stiffness block clamped by its fixed-capacity
  // eigensolver, the rigid bodies' Gauss–Newton rotational inertia
  ConstraintHessian const hessian = GENERATE(ConstraintHessian::GaussNewton, ConstraintHessian::GeometricStiffness,
                                             ConstraintHessian::GeometricStiffnessDiagonal);
  HessianProjection const projection = GENERATE(HessianProjection::WhenIndefinite, HessianProjection::Always);
  CAPTURE(ToString(hessian), ToString(projection));
  SceneParams params;
  params.newton.constraintHessian = hessian;
  params.newton.hessianProjection = projection;
  Chain chain = MakeChain(12, params);
  StepOk(*chain.scene, 1e-3, 2);
  RequireStepsAllocateNothing(*chain.scene, 1e-3, 20);
}

TEST_CASE("steps with sub-stepping enabled allocate nothing while it is not needed",
          "[scene][allocation][substep]") {
  // the policy costs nothing on steps that succeed whole (a retry's buffers
  // are sized by the first retry; a failed attempt's Error message allocates)
  SceneParams params;
  params.integrator = IntegratorType::Bdf2;
  params.substeps.maxSubsteps = 8;
  Chain chain = MakeChain(12, params);
  StepOk(*chain.scene, 1e-3, 2);
  RequireStepsAllocateNothing(*chain.scene, 1e-3, 20);
  REQUIRE(chain.scene->GetStats().substeppedSteps == 0);
}

TEST_CASE("deformable steps after the first allocate nothing", "[scene][allocation]") {
  SceneParams params;
  params.integrator = IntegratorType::Bdf2;
  auto scene = MakeScene(params);
  TetMesh mesh;
  Error error;
  REQUIRE(MakeTetBox(Real3::Zero(), Real3(0.3, 0.1, 0.1), {6, 2, 2}, mesh, error));
  DeformableActorParams p;
  p.nodes = mesh.nodes;
  p.tetrahedra = mesh.tetrahedra;
  p.triangles = {{0, 1, 7}, {1, 8, 7}, {1, 2, 8}};  // a shell patch on the bottom face, with hinges
  DeformableActor* block = scene->CreateDeformableActor(p, error);
  REQUIRE(block);
  REQUIRE(block->GetNumHinges() > 0);
  for (int i = 0; i < block->GetNumNodes(); ++i) {
    if (block->GetNodeReferencePosition(i).x() > 1e-9) continue;
    DeformableNodePositionConstraintParams pin;
    pin.actor = block->GetHandle();
    pin.nodeIndex = i;
    pin.position = block->GetNodePosition(i);
    pin.stiffness = 1e7;
    Constraint* c = scene->CreateDeformableNodePositionConstraint(pin, error);
    REQUIRE(c);
    REQUIRE(c->RegisterQuery(QueryType::ConstraintForce, error));
  }
  StepOk(*scene, 1e-2, 2);
  REQUIRE(scene->GetStats().linearSolver.find("CHOLMOD") != std::string::npos);
  RequireStepsAllocateNothing(*scene, 1e-2, 10);
}

TEST_CASE("steps that reuse a single-precision factor copy allocate nothing",
          "[scene][allocation][single]") {
  // a beam whose CHOLMOD factor is supernodal: its reused-factor CG applies
  // the float copy of L (SinglePrecisionFactor), made once per factorization
  SceneParams params;
  auto scene = MakeScene(params);
  DeformableActorParams p;
  p.youngModulus = 1e6;
  p.density = 1000;
  DeformableActor* beam = MakeBox(*scene, Real3::Zero(), Real3(0.6, 0.15, 0.15), {24, 6, 6}, p);
  PinNodes(*scene, *beam, 1e8, [](Real3 const& x) { return x.x() < 1e-9; });
  StepOk(*scene, 1.0 / 60, 2);
  RequireStepsAllocateNothing(*scene, 1.0 / 60, 10);
  REQUIRE(scene->GetStats().singlePrecisionSolves > 0);
}

TEST_CASE("rod steps after the first allocate nothing", "[scene][allocation][rod]") {
  // a rod clamped to a held rigid body (both rod couplings), drooping: every
  // rod path runs (stencil jets, frame transport, reference twist, the
  // RodElementRotationToRigid Jacobian)
  SceneParams params;
  params.integrator = IntegratorType::Bdf2;
  auto scene = MakeScene(params);
  RigidActorParams bodyParams;
  RigidActor* body = MakeRigid(*scene, bodyParams);
  Anchor(*scene, *body);
  RodActorParams rodParams;
  rodParams.radius = 0.005;
  rodParams.youngModulus = 1e8;
  RodActor* rod = MakeStraightRod(*scene, Real3::Zero(), Real3(1, 0.2, 0), 0.5, 30, rodParams);
  ClampRodEnd(*scene, *rod, *body, false, 1e8, 1e4);
  StepOk(*scene, 1e-2, 2);
  REQUIRE(scene->GetStats().linearSolver.find("CHOLMOD") != std::string::npos);
  RequireStepsAllocateNothing(*scene, 1e-2, 10);
  REQUIRE(rod->GetNodePosition(30).y() < 0.1 - 1e-3);  // it moved
}

TEST_CASE("articulated steps after the first allocate nothing", "[scene][allocation][articulated]") {
  // a 40-link spherical chain (120 DoFs): kinematics, composite inertias,
  // and the tree recursion's factorization and solves, or the dense block's
  // fill. The dense block with always-projected Hessians only: with exact
  // ones this falling chain's first Newton iteration of every step is
  // indefinite, and CHOLMOD's NotPositiveDefinite result allocates its
  // message (2 strings) before the projected retry (docs/articulated.md);
  // the tree's failed factorization allocates nothing, so it runs both ways
  auto const choice =
      GENERATE(std::make_pair(ArticulatedBlockSolve::Tree, HessianProjection::WhenIndefinite),
               std::make_pair(ArticulatedBlockSolve::Tree, HessianProjection::Always),
               std::make_pair(ArticulatedBlockSolve::Dense, HessianProjection::Always));
  ArticulatedBlockSolve const blockSolve = choice.first;
  HessianProjection const projection = choice.second;
  CAPTURE(ToString(blockSolve), static_cast<int>(projection));
  SceneParams params;
  params.integrator = IntegratorType::Bdf2;
  params.newton.hessianProjection = projection;
  auto scene = MakeScene(params);
  ArticulatedActorParams const chain = SphericalChain(40, blockSolve);
  Error error;
  ArticulatedActor* actor = scene->CreateArticulatedActor(chain, error);
  REQUIRE(actor);
  Articulated3dRotationTargetConstraintParams drive;
  drive.actor = actor->GetHandle();
  drive.jointIndex = 3;
  drive.stiffness = 10;
  drive.damping = 1;
  Constraint* c = scene->CreateArticulated3dRotationTargetConstraint(drive, error);
  REQUIRE(c);
  REQUIRE(c->RegisterQuery(QueryType::ConstraintForce, error));
  StepOk(*scene, 1e-2, 2);
  REQUIRE(scene->GetStats().linearSolver.find("CHOLMOD") != std::string::npos);
  REQUIRE(actor->IsSolvedOnTree() == (blockSolve == ArticulatedBlockSolve::Tree));
  RequireStepsAllocateNothing(*scene, 1e-2, 10);
  // the exact run did fall back to the modified tree factorization (at once,
  // without the scene's projected retry)
  if (blockSolve == ArticulatedBlockSolve::Tree) REQUIRE(actor->GetNumModifiedTreeFactorizations() > 0);
}

TEST_CASE("steps with the near-rigid cap allocate nothing", "[scene][allocation][near-rigid]") {
  // every actor's inverse-mass estimate (the articulated one's mass-matrix
  // diagonal in its composite scratch) and every constraint's cap, once per
  // stage; stiff constraints so that the cap applies
  SceneParams params;
  params.integrator = IntegratorType::Bdf2;
  params.newton.hessianProjection = HessianProjection::Always;  // the articulated chain, as above
  params.newton.nearRigidBeta = 1;
  Chain chain = MakeChain(4, params, 1e10);
  Scene& scene = *chain.scene;
  Error error;
  DeformableActorParams material;
  DeformableActor* box = MakeBox(scene, Real3(0, -1, 0), Real3(0.2, 0.1, 0.1), {2, 1, 1}, material);
  PinNodes(scene, *box, 1e12, [](Real3 const& x) { return x.x() < 1e-9; });
  RodActorParams rodParams;
  rodParams.radius = 0.005;
  RodActor* rod = MakeStraightRod(scene, Real3(0, 1, 0), Real3::UnitX(), 0.3, 6, rodParams);
  ClampRodEnd(scene, *rod, *chain.bodies[0], false, 1e12, 1e8);
  ArticulatedActorParams arm;
  for (int i = 0; i < 4; ++i) {
    ArticulatedLinkParams link;
    link.parent = i - 1;
    link.joint = i % 2 ? JointType::Spherical : JointType::Revolute;
    link.parentToJointPosition = i == 0 ? Real3(0, 2, 0) : Real3(0.1, 0, 0);
    link.inertia = Real3(1e-4, 1e-3, 1e-3);
    link.centerOfMass = Real3(0.05, 0, 0);
    arm.links.push_back(link);
  }
  ArticulatedActor* actor = scene.CreateArticulatedActor(arm, error);
  REQUIRE(actor);
  Articulated3dRotationTargetConstraintParams drive;
  drive.actor = actor->GetHandle();
  drive.jointIndex = 1;
  drive.stiffness = 1e9;
  REQUIRE(scene.CreateArticulated3dRotationTargetConstraint(drive, error));
  StepOk(scene, 1e-2, 2);
  REQUIRE(scene.GetStats().nearRigidConstraints > 0);
  RequireStepsAllocateNothing(scene, 1e-2, 10);
}

TEST_CASE("steps with constraints on articulated links allocate nothing", "[scene][allocation][articulated]") {
  // the 40-link chain's tip link holding a rigid ball (RigidSphericalJoint,
  // JointRotationTracking with the geometric stiffness) and a tet block's
  // node (DeformableNodeToRigid): on the tree, coupled with the ball and
  // the node by its Schur complement (exact and projected Hessians); on the
  // dense block, each constraint's J and curvature mapped onto the 120 path
  // DoFs (projected: see above for CHOLMOD's message on an indefinite first
  // iteration)
  // (the dense block only with projected Hessians)
  auto const [solve, projection] = GENERATE(table<ArticulatedBlockSolve, HessianProjection>(
      {{ArticulatedBlockSolve::Tree, HessianProjection::WhenIndefinite},
       {ArticulatedBlockSolve::Tree, HessianProjection::Always},
       {ArticulatedBlockSolve::Dense, HessianProjection::Always}}));
  CAPTURE(static_cast<int>(solve), static_cast<int>(projection));
  SceneParams params;
  params.integrator = IntegratorType::Bdf2;
  params.newton.hessianProjection = projection;
  params.newton.constraintHessian = ConstraintHessian::GeometricStiffness;
  auto scene = MakeScene(params);
  int const n = 40;
  ArticulatedActorParams const chain = SphericalChain(n, solve);
  Error error;
  ArticulatedActor* actor = MakeArticulated(*scene, chain);
  RigidActorParams body;
  body.position = Real3(0.1 * n, 0, 0);
  RigidActor* ball = MakeRigid(*scene, body);
  RigidSphericalJointConstraintParams joint;
  joint.actorA = actor->GetHandle();
  joint.linkA = n - 1;
  joint.localPosA = Real3(0.1, 0, 0);
  joint.actorB = ball->GetHandle();
  joint.stiffness = 1e5;
  REQUIRE(scene->CreateRigidSphericalJointConstraint(joint, error));
  JointRotationTrackingConstraintParams weld;
  weld.actorA = actor->GetHandle();
  weld.linkA = n - 1;
  weld.actorB = ball->GetHandle();
  weld.stiffness = 1e3;
  REQUIRE(scene->CreateJointRotationTrackingConstraint(weld, error));
  DeformableActor* block = MakeBox(*scene, Real3(0.1 * n + 0.2, -0.05, -0.05), Real3(0.1, 0.1, 0.1), {1, 1, 1},
                                   DeformableActorParams{});
  DeformableNodeToRigidConstraintParams hold;
  hold.deformableActor = block->GetHandle();
  hold.rigidActor = actor->GetHandle();
  hold.rigidLink = n - 1;
  hold.stiffness = 1e4;
  Constraint* held = scene->CreateDeformableNodeToRigidConstraint(hold, error);
  REQUIRE(held);
  REQUIRE(held->RegisterQuery(QueryType::ConstraintForce, error));
  StepOk(*scene, 1e-2, 2);
  REQUIRE(actor->IsSolvedOnTree() == (solve == ArticulatedBlockSolve::Tree));
  if (solve == ArticulatedBlockSolve::Tree) {
    REQUIRE(actor->GetNumCoupledConstraints() == 3);
    REQUIRE(actor->GetNumCoupledDofs() == 9);  // the ball's six, the node's three
  }
  RequireStepsAllocateNothing(*scene, 1e-2, 10);
}

TEST_CASE("steps with single-body constraints folded into the tree allocate nothing",
          "[scene][allocation][articulated][tree]") {
  // a RigidPivotPosition and a RigidPivotRotation on a 40-link chain's tip
  // link, taken into the tree recursion (exact and projected Hessians)
  HessianProjection const projection = GENERATE(HessianProjection::WhenIndefinite, HessianProjection::Always);
  CAPTURE(static_cast<int>(projection));
  SceneParams params;
  params.integrator = IntegratorType::Bdf2;
  params.newton.hessianProjection = projection;
  auto scene = MakeScene(params);
  int const n = 40;
  ArticulatedActorParams const chain = SphericalChain(n);
  Error error;
  ArticulatedActor* actor = MakeArticulated(*scene, chain);
  RigidPivotPositionConstraintParams pin;
  pin.actor = actor->GetHandle();
  pin.link = n - 1;
  pin.localPos = Real3(0.1, 0, 0);
  pin.position = Real3(0.1 * n, 0, 0);
  pin.stiffness = 1e4;
  Constraint* pinned = scene->CreateRigidPivotPositionConstraint(pin, error);
  REQUIRE(pinned);
  REQUIRE(pinned->RegisterQuery(QueryType::ConstraintForce, error));
  RigidPivotRotationConstraintParams turn;
  turn.actor = actor->GetHandle();
  turn.link = n - 1;
  turn.stiffness = 10;
  REQUIRE(scene->CreateRigidPivotRotationConstraint(turn, error));
  StepOk(*scene, 1e-2, 2);
  REQUIRE(actor->IsSolvedOnTree());
  RequireStepsAllocateNothing(*scene, 1e-2, 10);
}

TEST_CASE("contact steps allocate nothing once the contacts are set up", "[scene][allocation][contact]") {
  // a rigid box resting on the ground, a second box on it (body–body), a
  // tet cube beside them with its Surface (self contact on), each with
  // friction: per stage the candidate pairs, their contributors' DoF lists,
  // the bodies' trees and the friction anchors reuse their storage, and the
  // Newton iterations (assembly, safe step, energy) allocate nothing
  SceneParams params;
  params.gravity = Real3(0, -9.81, 0);
  auto scene = MakeScene(params);
  real const dhat = params.contact.activationDistance;
  MakeGround(*scene);
  MakeRigidBox(*scene, Real3(0, 0.1 + 0.5 * dhat, 0), Quat::Identity(), Real3::Constant(0.1), 1);
  MakeRigidBox(*scene, Real3(0, 0.3 + 1.5 * dhat, 0), Quat::Identity(), Real3::Constant(0.1), 1);
  TetMesh mesh;
  Error error;
  REQUIRE(MakeTetBox(Real3(0.3, 0.5 * dhat, 0), Real3::Constant(0.1), {2, 2, 2}, mesh, error));
  DeformableActorParams cube;
  cube.nodes = mesh.nodes;
  cube.tetrahedra = mesh.tetrahedra;
  cube.youngModulus = 1e6;
  DeformableActor* soft = MakeDeformable(*scene, cube);
  MakeSurface(*scene, *soft);
  StepOk(*scene, 1.0 / 60, 10);
  REQUIRE(scene->GetStats().activeContacts > 8);
  RequireStepsAllocateNothing(*scene, 1.0 / 60, 20);
}

TEST_CASE("link contact steps allocate nothing once the contacts are set up", "[scene][allocation][contact]") {
  // scene 8: the 5-link arm's capsules pushing a box (the link frames, the
  // path Jacobians and curvature, CCD along forward kinematics)
  SceneParams params;
  params.gravity = Real3(0, -9.81, 0);
  params.newton.hessianProjection = HessianProjection::WhenIndefinite;
  auto scene = MakeScene(params);
  ArmPush const push = MakeArmPush(*scene);
  Error error;
  real const dt = 1.0 / 60;
  for (int s = 0; s < 40; ++s) {
    REQUIRE(push.carriage->SetTargetDof(push.start + push.speed * s * dt, error));
    REQUIRE(scene->Step(dt, error));
  }
  REQUIRE(scene->GetStats().activeContacts > 4);  // the box on the ground and the capsule on the box
  int const during = CountAllocations([&] {
                       for (int s = 40; s < 60; ++s) {
                         (void)push.carriage->SetTargetDof(push.start + push.speed * s * dt, error);
                         if (!scene->Step(dt, error)) break;
                       }
                     }).superdex;
  INFO(error.ToString());
  REQUIRE_FALSE(error);
  REQUIRE(during == 0);
}

// Bad input gives a clear Error (code + message naming the field and value)
// and changes nothing.
#include "test_scenes.h"

#include <limits>

using namespace superdex;
using namespace superdex::test;

namespace {
constexpr real kNaN = std::numeric_limits<real>::quiet_NaN();
constexpr real kInf = std::numeric_limits<real>::infinity();

struct Pinned {
  std::unique_ptr<Scene> scene;
  RigidActor* body;
  Constraint* pin;
};

Pinned MakePinned() {
  Pinned p;
  p.scene = MakeScene();
  p.body = MakeRigid(*p.scene, {});
  RigidPivotPositionConstraintParams params;
  params.actor = p.body->GetHandle();
  params.stiffness = 100;
  params.damping = 1;
  Error error;
  p.pin = p.scene->CreateRigidPivotPositionConstraint(params, error);
  REQUIRE(p.pin);
  return p;
}
}  // namespace

TEST_CASE("negative or non-finite stiffness and damping are rejected", "[scene][input]") {
  Pinned p = MakePinned();
  real const bad = GENERATE(-1.0, kNaN, kInf, -kInf);
  CAPTURE(bad);
  Error error;
  REQUIRE_FALSE(p.pin->SetStiffness(bad, error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
  REQUIRE(Mentions(error, "stiffness"));
  REQUIRE(p.pin->GetStiffness() == 100);
  error.Clear();
  REQUIRE_FALSE(p.pin->SetDamping(bad, error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
  REQUIRE(Mentions(error, "damping"));
  REQUIRE(p.pin->GetDamping() == 1);
  error.Clear();
  if (!std::isfinite(bad)) {
    REQUIRE_FALSE(p.pin->SetSaturation(bad, error));
    REQUIRE(Mentions(error, "saturation"));
  }
  // the same values in creation params: no constraint is created
  error.Clear();
  RigidPivotPositionConstraintParams params;
  params.actor = p.body->GetHandle();
  params.stiffness = bad;
  REQUIRE_FALSE(p.scene->CreateRigidPivotPositionConstraint(params, error));
  REQUIRE(Mentions(error, "RigidPivotPositionConstraintParams.stiffness"));
  params.stiffness = 1;
  params.damping = bad;
  error.Clear();
  REQUIRE_FALSE(p.scene->CreateRigidPivotPositionConstraint(params, error));
  REQUIRE(Mentions(error, "RigidPivotPositionConstraintParams.damping"));
  REQUIRE(p.scene->GetNumConstraints() == 1);
}

TEST_CASE("non-positive or non-finite dt is rejected", "[scene][input]") {
  Pinned p = MakePinned();
  StepOk(*p.scene, 1e-3, 2);
  Real3 const position = p.body->GetPosition();
  real const time = p.scene->GetTime();
  real const bad = GENERATE(0.0, -1e-3, kNaN, kInf);
  CAPTURE(bad);
  Error error;
  REQUIRE_FALSE(p.scene->Step(bad, error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
  REQUIRE(Mentions(error, "dt"));
  REQUIRE(p.scene->GetTime() == time);
  REQUIRE(p.body->GetPosition() == position);
}

TEST_CASE("a non-unit quaternion is rejected", "[scene][input]") {
  Pinned p = MakePinned();
  Quat const bad = GENERATE(Quat(2, 0, 0, 0), Quat(0, 0, 0, 0), Quat(0.9, 0, 0, 0), Quat(kNaN, 0, 0, 0));
  Error error;
  RigidActorParams params;
  params.rotation = bad;
  REQUIRE_FALSE(p.scene->CreateRigidActor(params, error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
  REQUIRE(Mentions(error, "RigidActorParams.rotation"));
  REQUIRE(p.scene->GetNumActors() == 1);
  error.Clear();
  Quat const rotation = p.body->GetRotation();
  REQUIRE_FALSE(p.body->SetPose(Real3::Zero(), bad, error));
  REQUIRE(Mentions(error, "rotation"));
  REQUIRE(p.body->GetRotation().coeffs() == rotation.coeffs());
}

TEST_CASE("non-positive mass or inertia is rejected", "[scene][input]") {
  auto scene = MakeScene();
  Error error;
  SECTION("mass") {
    real const bad = GENERATE(0.0, -2.0, kNaN, kInf);
    RigidActorParams params;
    params.mass = bad;
    REQUIRE_FALSE(scene->CreateRigidActor(params, error));
    REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
    REQUIRE(Mentions(error, "RigidActorParams.mass"));
  }
  SECTION("inertia") {
    Real3 const bad = GENERATE(Real3(0, 1, 1), Real3(1, -1, 1), Real3(1, 1, kNaN));
    RigidActorParams params;
    params.inertia = bad;
    REQUIRE_FALSE(scene->CreateRigidActor(params, error));
    REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
    REQUIRE(Mentions(error, "RigidActorParams.inertia"));
  }
  REQUIRE(scene->GetNumActors() == 0);
}

TEST_CASE("stale handles are detected", "[scene][input]") {
  Pinned p = MakePinned();
  Scene& scene = *p.scene;
  ActorHandle const actor = p.body->GetHandle();
  ConstraintHandle const pin = p.pin->GetHandle();
  RigidActor* other = MakeRigid(scene, {});
  Error error;

  REQUIRE(scene.DestroyActor(actor, error));
  // destroying the actor destroyed its constraint
  REQUIRE(scene.GetActor(actor) == nullptr);
  REQUIRE(scene.GetConstraint(pin) == nullptr);
  REQUIRE(scene.GetNumConstraints() == 0);

  // a new actor reuses the slot but not the handle
  RigidActor* reused = MakeRigid(scene, {});
  REQUIRE(reused->GetHandle().index == actor.index);
  REQUIRE(scene.GetActor(actor) == nullptr);

  REQUIRE_FALSE(scene.DestroyActor(actor, error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidHandle);
  error.Clear();
  REQUIRE_FALSE(scene.DestroyConstraint(pin, error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidHandle);
  error.Clear();
  RigidSphericalJointConstraintParams joint;
  joint.actorA = actor;
  joint.actorB = other->GetHandle();
  REQUIRE_FALSE(scene.CreateRigidSphericalJointConstraint(joint, error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidHandle);
  REQUIRE(Mentions(error, "actorA"));
  error.Clear();
  RigidPivotPositionConstraintParams pivot;  // a default (null) handle
  REQUIRE_FALSE(scene.CreateRigidPivotPositionConstraint(pivot, error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidHandle);
  REQUIRE(scene.GetNumActors() == 2);
  REQUIRE(scene.GetNumConstraints() == 0);
  StepOk(scene, 1e-3);
}

TEST_CASE("scene parameters are validated", "[scene][input]") {
  Error error;
  SceneParams params;
  params.gravity = Real3(0, kNaN, 0);
  REQUIRE_FALSE(Scene::Create(params, error));
  REQUIRE(Mentions(error, "SceneParams.gravity"));
  error.Clear();
  params = {};
  params.newton.velocityTolerance = 0;
  REQUIRE_FALSE(Scene::Create(params, error));
  REQUIRE(Mentions(error, "velocityTolerance"));
  error.Clear();
  params = {};
  params.newton.maxIterations = 0;
  REQUIRE_FALSE(Scene::Create(params, error));
  REQUIRE(Mentions(error, "maxIterations"));
}

TEST_CASE("a joint between a body and itself is rejected", "[scene][input]") {
  Pinned p = MakePinned();
  RigidSphericalJointConstraintParams joint;
  joint.actorA = joint.actorB = p.body->GetHandle();
  Error error;
  REQUIRE_FALSE(p.scene->CreateRigidSphericalJointConstraint(joint, error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
  REQUIRE(Mentions(error, "actorB"));
}

TEST_CASE("rod masses and stiffnesses that under- or overflow are refused, naming the inputs",
          "[scene][input][rod]") {
  auto scene = MakeScene();
  RodActorParams good;
  good.nodes = {Real3(0, 0, 0), Real3(0.5, 0, 0), Real3(1, 0, 0)};
  auto const expectError = [&](auto const& p, std::string const& mention) {
    RequireActorRefused(*scene, p, mention);
  };
  // before: each was accepted, and the first step failed
  RodActorParams p = good;
  p.radius = 1e300;  // area overflows: infinite masses
  expectError(p, "radius 1.0000000000000001e+300");
  expectError(p, "gets mass inf");
  p.radius = 1e-300;  // area underflows: zero masses
  expectError(p, "gets mass 0");
  p = good;
  p.density = 5e-324;
  expectError(p, "gets mass 0 and twist inertia 0 from density 4.94065645841246");
  p = good;
  p.radius = 1e-80;  // I = π r⁴/4 ≈ 7.9e-321: masses and inertias fine, E·I underflows
  p.density = 1e150;
  p.youngModulus = 1e-20;
  expectError(p, "bending E·I1 stiffness 0");
  // the field that is wrong is named (before: the second moment of area,
  // and "zero length")
  p = good;
  p.sectionArea = std::numeric_limits<real>::infinity();
  p.secondMomentOfArea1 = p.secondMomentOfArea2 = p.torsionConstant = 1e-8;
  expectError(p, "sectionArea");
  p = good;
  p.nodes = {Real3(0, 0, 0), Real3(1e200, 0, 0), Real3(-1e200, 1, 0)};
  expectError(p, "element 0 (nodes 0, 1");
  expectError(p, "is too long: its length overflows");
  Error error;
  REQUIRE(scene->CreateRodActor(good, error));
}

TEST_CASE("articulated initial states and axes that overflow are refused", "[scene][input][articulated]") {
  auto scene = MakeScene();
  auto const expectError = [&](auto const& p, std::string const& mention) {
    RequireActorRefused(*scene, p, mention);
  };
  ArticulatedActorParams p;
  p.links.resize(1);
  p.links[0].joint = JointType::Spherical;
  // before: accepted with a NaN link rotation
  p.links[0].initialPosition = {1e300, 0, 1e300};
  expectError(p, "ArticulatedActorParams.links[0].initialPosition[0..2]");
  expectError(p, "angle (its norm) overflows");
  // a huge prismatic offset overflows the link's position
  p.links[0].joint = JointType::Prismatic;
  p.links[0].axis = Real3(1, 0, 0);
  p.links[0].initialPosition = {1.5e308};
  p.links[0].jointToChildPosition = Real3(1.5e308, 0, 0);
  expectError(p, "links[0]: the link's initial pose overflows");

  // before: a 1e200 axis normalized to zero (the joint froze, the step failed)
  ArticulatedActorParams big, unit;
  big.links.resize(1);
  big.links[0].joint = JointType::Revolute;
  big.links[0].axis = Real3(0, 0, 1e200);
  big.links[0].jointToChildPosition = Real3(0.5, 0, 0);
  big.links[0].initialVelocity = {1};
  unit = big;
  unit.links[0].axis = Real3(0, 0, 1);
  Error error;
  ArticulatedActor* a = scene->CreateArticulatedActor(big, error);
  ArticulatedActor* b = scene->CreateArticulatedActor(unit, error);
  REQUIRE(a);
  REQUIRE(b);
  StepOk(*scene, 1e-2, 5);
  REQUIRE((a->GetLinkPosition(0) - b->GetLinkPosition(0)).norm() < 1e-12);
  REQUIRE(a->GetLinkPosition(0).y() > 0.01);  // it turned about z
}

TEST_CASE("the dense solver refuses a scene above kDenseSolverMaxUnknowns, and nothing changes",
          "[scene][input]") {
  // before: ~12,000 DoFs ran for minutes with no guard
  SceneParams params;
  params.linearSolver = LinearSolverType::Dense;
  auto scene = MakeScene(params);
  TetMesh mesh;
  Error error;
  REQUIRE(MakeTetBox(Real3::Zero(), Real3(1, 0.1, 0.1), {40, 4, 4}, mesh, error));  // 41·5·5 nodes
  DeformableActorParams soft;
  soft.nodes = mesh.nodes;
  soft.tetrahedra = mesh.tetrahedra;
  REQUIRE(scene->CreateDeformableActor(soft, error));
  REQUIRE(scene->GetNumDofs() == 3075);
  DeformableActor* second = scene->CreateDeformableActor(soft, error);
  REQUIRE(second);
  REQUIRE(scene->GetNumDofs() > kDenseSolverMaxUnknowns);
  real const time = scene->GetTime();
  Real3 const before = second->GetNodePosition(7);
  REQUIRE_FALSE(scene->Step(1e-3, error));
  REQUIRE(error.GetCode() == ErrorCode::LinearSolverFailed);
  REQUIRE(Mentions(error, "at most kDenseSolverMaxUnknowns = 5000 unknowns, got 6150"));
  REQUIRE(scene->GetTime() == time);
  REQUIRE(second->GetNodePosition(7) == before);
  // switching to it on a scene that large is refused up front
  REQUIRE(scene->SetLinearSolver(LinearSolverType::Cholmod, {}, error));
  error.Clear();
  REQUIRE_FALSE(scene->SetLinearSolver(LinearSolverType::Dense, {}, error));
  REQUIRE(Mentions(error, "this scene has 6150 DoFs"));
  REQUIRE(scene->GetParams().linearSolver == LinearSolverType::Cholmod);
  StepOk(*scene, 1e-3);
}

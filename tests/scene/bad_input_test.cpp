// Bad input gives a clear Error (code + message naming the field and value)
// and changes nothing.
#include "test_scenes.h"

#include <limits>

using namespace superdex;
using namespace superdex::test;

namespace {
constexpr real kNaN = std::numeric_limits<real>::quiet_NaN();
constexpr real kInf = std::numeric_limits<real>::infinity();

bool Mentions(Error const& e, std::string const& part) {
  return e.GetMessage().find(part) != std::string::npos;
}

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

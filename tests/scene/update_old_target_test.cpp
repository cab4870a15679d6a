// Teleporting a damped pivot target: with UpdateOldTarget the next step has
// no damping impulse; without it, the target jump enters Δg and the damper
// kicks the body (backward Euler: v₁ = d·jump/(m + d h), from
// m v₁/h = −(d/h)(h v₁ − jump)).
#include "test_support.h"

using namespace superdex;
using namespace superdex::test;

namespace {
constexpr real kMass = 3, kDamping = 40, kDt = 1e-2;
const Real3 kJump(0.2, -0.1, 0.05);

struct Damper {
  std::unique_ptr<Scene> scene;
  RigidActor* body;
  Constraint* pivot;
};

// a pure damper (k = 0) on a body at rest at its target, no gravity
Damper MakeDamper() {
  SceneParams params;
  params.gravity = Real3::Zero();
  params.newton.velocityTolerance = 1e-12;
  Damper d;
  d.scene = MakeScene(params);
  RigidActorParams body;
  body.mass = kMass;
  d.body = MakeRigid(*d.scene, body);
  RigidPivotPositionConstraintParams p;
  p.actor = d.body->GetHandle();
  p.damping = kDamping;
  Error error;
  d.pivot = d.scene->CreateRigidPivotPositionConstraint(p, error);
  REQUIRE(d.pivot);
  StepOk(*d.scene, kDt, 3);  // at rest: nothing moves
  REQUIRE(d.body->GetLinearVelocity().norm() == 0);
  return d;
}
}  // namespace

TEST_CASE("UpdateOldTarget removes the damping impulse of a teleported target", "[scene][target]") {
  Error error;
  SECTION("with UpdateOldTarget: no impulse") {
    Damper d = MakeDamper();
    REQUIRE(d.pivot->SetTargetPosition(kJump, error));
    REQUIRE(d.pivot->UpdateOldTarget(error));
    StepOk(*d.scene, kDt);
    real const impulse = kMass * d.body->GetLinearVelocity().norm();
    CAPTURE(impulse);
    REQUIRE(impulse <= 1e-12);
  }
  SECTION("without UpdateOldTarget: the damper kicks") {
    Damper d = MakeDamper();
    REQUIRE(d.pivot->SetTargetPosition(kJump, error));
    StepOk(*d.scene, kDt);
    Real3 const expected = kDamping * kJump / (kMass + kDamping * kDt);
    Real3 const velocity = d.body->GetLinearVelocity();
    CAPTURE(velocity.transpose(), expected.transpose());
    REQUIRE(expected.norm() > 1);
    REQUIRE((velocity - expected).norm() <= 1e-9 * expected.norm());
  }
  SECTION("a target moved without a teleport keeps moving the body on later steps") {
    Damper d = MakeDamper();
    REQUIRE(d.pivot->SetTargetPosition(kJump, error));
    StepOk(*d.scene, kDt);
    // next step: the target is now still, its old target was updated at the
    // end of the step, so only the body's own motion is damped
    Real3 const before = d.body->GetLinearVelocity();
    StepOk(*d.scene, kDt);
    Real3 const after = d.body->GetLinearVelocity();
    REQUIRE(after.norm() < before.norm());
  }
}

TEST_CASE("UpdateOldTarget on a constraint without a target is an error", "[scene][target]") {
  auto scene = MakeScene();
  RigidActor* a = MakeRigid(*scene, {});
  RigidActorParams pb;
  pb.position = Real3(1, 0, 0);
  RigidActor* b = MakeRigid(*scene, pb);
  RigidSphericalJointConstraintParams p;
  p.actorA = a->GetHandle();
  p.actorB = b->GetHandle();
  Error error;
  Constraint* joint = scene->CreateRigidSphericalJointConstraint(p, error);
  REQUIRE(joint);
  REQUIRE_FALSE(joint->UpdateOldTarget(error));
  REQUIRE(error.GetCode() == ErrorCode::NotSupported);
  REQUIRE(error.GetMessage().find("RigidSphericalJoint") != std::string::npos);
  error.Clear();
  REQUIRE_FALSE(joint->SetTargetPosition(Real3::Zero(), error));
  REQUIRE(error.GetCode() == ErrorCode::NotSupported);
}

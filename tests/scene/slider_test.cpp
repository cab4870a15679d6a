// Prismatic + tracking = slider: a body joined to a fixed body by a
// RigidPrismaticJoint and a JointRotationTracking slides freely along the
// axis, holds its transverse deviation at the compliance value and its
// relative rotation at the target; travel limits stop it at the bound.
//
// The force is gravity, tilted so that it has a component along the slide
// axis (world x) and one across it: g = (3, −4, 0) m/s².
#include "test_scenes.h"

#include <iostream>
#include <numbers>

using namespace superdex;
using namespace superdex::test;

namespace {
constexpr real kMassB = 2;
constexpr real kStiffness = 1e5;  // prismatic joint [N/m]
const Real3 kGravity(3, -4, 0);

struct Slider {
  std::unique_ptr<Scene> scene;
  RigidActor* base;
  RigidActor* slider;
  Constraint* prismatic;
  Constraint* tracking;
};

Slider MakeSlider(real upperLimit, real damping) {
  SceneParams params;
  params.gravity = kGravity;
  params.newton.velocityTolerance = 1e-9;
  Slider s;
  s.scene = MakeScene(params);
  RigidActorParams base;
  base.mass = 5;
  base.inertia = Real3(0.3, 0.4, 0.5);
  s.base = MakeRigid(*s.scene, base);
  Anchor(*s.scene, *s.base);
  RigidActorParams slider;
  slider.mass = kMassB;
  slider.inertia = Real3(0.1, 0.2, 0.3);
  slider.position = Real3(0.4, 0.1, -0.2);
  slider.rotation = Quat(Eigen::AngleAxis<real>(0.3, Real3(1, 2, 3).normalized()));
  s.slider = MakeRigid(*s.scene, slider);

  Error error;
  RigidPrismaticJointConstraintParams p;
  p.actorA = s.base->GetHandle();
  p.actorB = s.slider->GetHandle();
  // the joint frame's z axis (the free axis) along world x
  p.jointFrame = Quat(Eigen::AngleAxis<real>(std::numbers::pi / 2, Real3::UnitY()));
  p.upperLimit = upperLimit;
  p.stiffness = kStiffness;
  p.damping = damping;
  s.prismatic = s.scene->CreateRigidPrismaticJointConstraint(p, error);
  REQUIRE(s.prismatic);
  JointRotationTrackingConstraintParams t;
  t.actorA = s.base->GetHandle();
  t.actorB = s.slider->GetHandle();
  t.stiffness = 1e4;
  t.damping = 10;
  s.tracking = s.scene->CreateJointRotationTrackingConstraint(t, error);
  REQUIRE(s.tracking);
  return s;
}
}  // namespace

TEST_CASE("a prismatic joint with rotation tracking slides freely along its axis", "[scene][slider]") {
  Slider s = MakeSlider(std::numeric_limits<real>::infinity(), 200);
  real const dt = 1e-3;
  StepOk(*s.scene, dt, 300);  // transverse transient dies out (damped)
  real const v1 = s.slider->GetLinearVelocity().x();
  real const t1 = s.scene->GetTime();
  StepOk(*s.scene, dt, 500);
  real const v2 = s.slider->GetLinearVelocity().x();
  real const acceleration = (v2 - v1) / (s.scene->GetTime() - t1);
  CAPTURE(acceleration);
  // free along the axis: a = F/m = g_x
  REQUIRE(std::abs(acceleration - kGravity.x()) <= 0.01 * kGravity.x());

  // across the axis the joint holds the weight's transverse part at F⊥/k
  Real3 const g = ToReal3(s.prismatic->GetDeviation());
  real const expected = kMassB * std::abs(kGravity.y()) / kStiffness;
  CAPTURE(g.transpose(), expected);
  REQUIRE(g.z() == 0);  // no travel limits
  REQUIRE(std::abs(g.head<2>().norm() - expected) <= 0.01 * expected);
  // the transverse displacement is along world −y, where the weight pulls
  REQUIRE(s.slider->GetPosition().y() < 0.1);

  // the relative rotation stays at its target (no torque acts on the slider)
  real const rotationError = ToReal3(s.tracking->GetDeviation()).norm();
  CAPTURE(rotationError);
  REQUIRE(rotationError <= 1e-6);
  std::cout << "slider: a = " << acceleration << " (F/m = " << kGravity.x() << "), |g_perp| = "
            << g.head<2>().norm() << " (F_perp/k = " << expected << "), rotation error "
            << rotationError << " rad\n";
  REQUIRE(s.slider->GetPosition().x() > 0.4 + 0.5 * kGravity.x() * 0.7 * 0.7);
}

TEST_CASE("travel limits stop the slider at the bound", "[scene][slider]") {
  real const upper = 0.05;
  Slider s = MakeSlider(upper, 300);
  auto* prismatic = static_cast<RigidPrismaticJointConstraint*>(s.prismatic);
  StepOk(*s.scene, 1e-3, 3000);
  // at rest against the stop: the limit's violation carries the axial weight
  Real3 const g = ToReal3(s.prismatic->GetDeviation());
  real const expected = kMassB * kGravity.x() / kStiffness;
  CAPTURE(g.transpose(), expected, prismatic->GetOffset().transpose());
  REQUIRE(s.slider->GetLinearVelocity().norm() <= 1e-6);
  std::cout << "slider at the stop: violation " << g.z() << " (F/k = " << expected << ")\n";
  REQUIRE(std::abs(g.z() - expected) <= 0.01 * expected);
  REQUIRE(std::abs(prismatic->GetOffset().z() - (upper + expected)) <= 0.01 * expected);
  // the travel limits are not reported as range limits (reference page)
  Error error;
  REQUIRE(s.prismatic->GetLimitMaxValues(error).empty());
  REQUIRE(error.GetCode() == ErrorCode::NotSupported);
}

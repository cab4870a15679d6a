// A rigid body hung from a RigidPivotPosition: the compound-pendulum period
// and the static deviation m g / k.
#include "test_scenes.h"

#include <cmath>
#include <numbers>

using namespace superdex;
using namespace superdex::test;

namespace {
constexpr real kMass = 2;
constexpr real kArm = 0.5;  // pivot to centre of mass [m]
const Real3 kInertia{0.1, 0.2, 0.3};
constexpr real kStiffness = 1e8;
constexpr real kDt = 1e-3;

// pivot at the world origin, body rotated by `angle` about z
Pendulum MakePendulum(real angle, IntegratorType integrator) {
  SceneParams params;
  params.integrator = integrator;
  params.newton.velocityTolerance = 1e-9;
  return test::MakePendulum(params, kMass, kInertia, kArm, kStiffness, angle);
}
}  // namespace

TEST_CASE("compound pendulum swings at its analytic period", "[scene][pendulum]") {
  IntegratorType const integrator = GENERATE(IntegratorType::BackwardEuler, IntegratorType::Bdf2);
  CAPTURE(ToString(integrator));
  real const g = 9.81;
  real const expected =
      2 * std::numbers::pi * std::sqrt((kInertia.z() + kMass * kArm * kArm) / (kMass * g * kArm));
  Pendulum p = MakePendulum(0.02, integrator);

  // upward zero crossings of the swing angle, linearly interpolated
  DynamicArray<real> crossings;
  real previousAngle = Log(p.body->GetRotation()).z();
  for (int step = 0; step < static_cast<int>(3.5 * expected / kDt); ++step) {
    StepOk(*p.scene, kDt);
    real const angle = Log(p.body->GetRotation()).z();
    if (previousAngle < 0 && angle >= 0)
      crossings.push_back(p.scene->GetTime() - kDt * angle / (angle - previousAngle));
    previousAngle = angle;
  }
  REQUIRE(crossings.size() >= 3);
  real const measured = (crossings.back() - crossings.front()) / (crossings.size() - 1);
  CAPTURE(measured, expected);
  REQUIRE(std::abs(measured - expected) <= 0.01 * expected);
}

TEST_CASE("a body hanging at rest deviates by m g / k", "[scene][pendulum]") {
  Pendulum p = MakePendulum(0, IntegratorType::BackwardEuler);
  StepOk(*p.scene, kDt, 50);
  Real3 const deviation = ToReal3(p.pin->GetDeviation());
  real const expected = kMass * 9.81 / kStiffness;
  CAPTURE(deviation.transpose(), expected);
  REQUIRE(deviation.norm() > 0);
  REQUIRE(std::abs(deviation.norm() - expected) <= 0.01 * expected);
  // the body hangs below the pivot: the pivot point sits below its target
  REQUIRE(deviation.y() < 0);
}

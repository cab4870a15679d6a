// Animated targets: a RigidPivotPosition target moved along a circle drags
// the body along it with the steady-state tracking error of a driven
// spring–damper; a RigidPivotRotation target spun at a constant rate spins
// the body at that rate.
#include "test_scenes.h"

#include <cmath>
#include <iostream>
#include <numbers>

using namespace superdex;
using namespace superdex::test;

TEST_CASE("a pivot target moved along a circle drags the body along it", "[long][scene][target]") {
  // m ẍ = −k (x − p) − d (ẋ − ṗ), p = ρ (cos Ωt, sin Ωt, 0): the error
  // e = x − p has the steady amplitude |e| = ρ m Ω² / √((k − mΩ²)² + (dΩ)²)
  real const mass = 1, stiffness = 400, damping = 10, radius = 0.2;
  real const omega = 2 * std::numbers::pi;
  real const dt = 1e-4;
  real const expected = radius * mass * omega * omega /
                        std::hypot(stiffness - mass * omega * omega, damping * omega);
  SceneParams params;
  params.gravity = Real3::Zero();
  params.newton.velocityTolerance = 1e-10;
  auto scene = MakeScene(params);
  RigidActorParams body;
  body.mass = mass;
  body.position = Real3(radius, 0, 0);
  body.linearVelocity = Real3(0, radius * omega, 0);
  RigidActor* actor = MakeRigid(*scene, body);
  RigidPivotPositionConstraintParams p;
  p.actor = actor->GetHandle();
  p.position = body.position;
  p.stiffness = stiffness;
  p.damping = damping;
  Error error;
  Constraint* pivot = scene->CreateRigidPivotPositionConstraint(p, error);
  REQUIRE(pivot);

  auto target = [&](real t) { return Real3(radius * std::cos(omega * t), radius * std::sin(omega * t), 0); };
  real smallest = INFINITY, largest = 0;
  int const steps = static_cast<int>(std::lround(4.0 / dt));
  for (int n = 1; n <= steps; ++n) {
    // the target of the stage is the one at its end time
    REQUIRE(pivot->SetTargetPosition(target(n * dt), error));
    StepOk(*scene, dt);
    if (n * dt >= 3.0) {  // transients decay as exp(−d t/2m): e⁻¹⁵ by t = 3 s
      real const e = ToReal3(pivot->GetDeviation()).norm();
      smallest = std::min(smallest, e);
      largest = std::max(largest, e);
    }
  }
  std::cout << "circle tracking: error in [" << smallest << ", " << largest << "], predicted "
            << expected << "\n";
  CAPTURE(smallest, largest, expected);
  // the error is a constant-length vector rotating with the target
  REQUIRE(std::abs(smallest - expected) <= 0.01 * expected);
  REQUIRE(std::abs(largest - expected) <= 0.01 * expected);
}

TEST_CASE("a rotation target spun at a constant rate spins the body at that rate", "[long][scene][target]") {
  real const rate = 3;  // [rad/s] about world z
  real const dt = 1e-3;
  SceneParams params;
  params.gravity = Real3::Zero();
  params.newton.velocityTolerance = 1e-10;
  auto scene = MakeScene(params);
  RigidActorParams body;
  body.inertia = Real3(0.1, 0.2, 0.3);
  RigidActor* actor = MakeRigid(*scene, body);
  RigidPivotRotationConstraintParams p;
  p.actor = actor->GetHandle();
  p.localRotation = Quat(Eigen::AngleAxis<real>(0.4, Real3::UnitX()));  // a tilted pivot frame
  p.rotation = p.localRotation;  // starts satisfied
  p.stiffness = 50;
  p.damping = 2;
  Error error;
  Constraint* pivot = scene->CreateRigidPivotRotationConstraint(p, error);
  REQUIRE(pivot);

  int const steps = 4000;
  for (int n = 1; n <= steps; ++n) {
    Quat const spin(Eigen::AngleAxis<real>(rate * n * dt, Real3::UnitZ()));
    REQUIRE(pivot->SetTargetRotation(spin * p.rotation, error));
    StepOk(*scene, dt);
  }
  Real3 const omega = actor->GetAngularVelocity();
  real const lag = ToReal3(pivot->GetDeviation()).norm();
  std::cout << "spun target: body angular velocity " << omega.transpose() << " (target " << rate
            << " about z), lag " << lag << " rad\n";
  CAPTURE(omega.transpose(), lag);
  REQUIRE(std::abs(omega.z() - rate) <= 0.01 * rate);
  REQUIRE(omega.head<2>().norm() <= 0.01 * rate);
  REQUIRE(lag < 0.05);
}

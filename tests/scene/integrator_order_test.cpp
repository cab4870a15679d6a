// Convergence order of the integrators on an undamped linear spring–mass: a
// body on a RigidPivotPosition at its centre of mass (g = t − p̂, linear),
// no gravity, ω = 2π rad/s, released from rest at x₀. Exact: x = x₀ cos ωt.
#include "test_support.h"

#include <cmath>
#include <iostream>
#include <numbers>

using namespace superdex;
using namespace superdex::test;

namespace {
constexpr real kMass = 1.5;
constexpr real kAmplitude = 0.1;
constexpr real kEndTime = 1.0;

// error at t = 1 s in the energy norm: sqrt(Δx² + (Δv/ω)²)
real ErrorAtEnd(IntegratorType integrator, real dt) {
  real const omega = 2 * std::numbers::pi;
  SceneParams params;
  params.gravity = Real3::Zero();
  params.integrator = integrator;
  params.newton.velocityTolerance = 1e-12;
  auto scene = MakeScene(params);
  RigidActorParams body;
  body.mass = kMass;
  body.position = Real3(kAmplitude, 0, 0);
  RigidActor* actor = MakeRigid(*scene, body);
  RigidPivotPositionConstraintParams spring;
  spring.actor = actor->GetHandle();
  spring.stiffness = kMass * omega * omega;
  Error error;
  REQUIRE(scene->CreateRigidPivotPositionConstraint(spring, error));
  int const steps = static_cast<int>(std::lround(kEndTime / dt));
  StepOk(*scene, dt, steps);
  real const t = scene->GetTime();
  real const dx = actor->GetPosition().x() - kAmplitude * std::cos(omega * t);
  real const dv = actor->GetLinearVelocity().x() + kAmplitude * omega * std::sin(omega * t);
  return std::sqrt(dx * dx + (dv / omega) * (dv / omega));
}

}  // namespace

TEST_CASE("backward Euler converges at order 1 and BDF2 at order 2", "[scene][integrator]") {
  auto const [integrator, expectedOrder] = GENERATE(
      std::pair{IntegratorType::BackwardEuler, 1.0}, std::pair{IntegratorType::Bdf2, 2.0});
  CAPTURE(ToString(integrator));
  DynamicArray<real> dts, errors;
  for (real dt : {1.0 / 100, 1.0 / 200, 1.0 / 400, 1.0 / 800, 1.0 / 1600}) {
    dts.push_back(dt);
    errors.push_back(ErrorAtEnd(integrator, dt));
    std::cout << ToString(integrator) << " dt = " << dt << "  error = " << errors.back() << "\n";
    REQUIRE(errors.back() > 0);
  }
  real const order = FitOrder(dts, errors);
  std::cout << ToString(integrator) << " fitted order = " << order << "\n";
  CAPTURE(order);
  // errors are far above round-off at these steps, so the fitted order is
  // within 0.1 of the theoretical one
  REQUIRE(std::abs(order - expectedOrder) <= 0.1);
}

TEST_CASE("a torque-free asymmetric body: backward Euler keeps its angular momentum, BDF2 to second order",
          "[scene][integrator][rigid]") {
  // principal inertia 1e-3, 4e-3, 6e-3 kg m², spun at (0.5, 2, -1) rad/s: it
  // tumbles; 1 s of steps. Backward Euler's rotation target is the
  // momentum-conserving one (rigid_actor.h); BDF2's chart-consistent target
  // (rigid_inertia.cc) loses |ΔL|/|L| ∝ dt²
  auto drift = [](IntegratorType integrator, real dt) {
    SceneParams params;
    params.gravity = Real3::Zero();
    params.integrator = integrator;
    params.newton.velocityTolerance = 1e-10;
    auto scene = MakeScene(params);
    RigidActorParams body;
    body.inertia = Real3(1e-3, 4e-3, 6e-3);
    body.angularVelocity = Real3(0.5, 2.0, -1.0);
    RigidActor* actor = MakeRigid(*scene, body);
    Real3 const l0 = actor->GetAngularMomentum();
    StepOk(*scene, dt, static_cast<int>(std::lround(1 / dt)));
    return (actor->GetAngularMomentum() - l0).norm() / l0.norm();
  };
  for (real dt : {1.0 / 100, 1.0 / 400}) REQUIRE(drift(IntegratorType::BackwardEuler, dt) <= 1e-10);
  DynamicArray<real> dts, drifts;
  for (real dt : {1.0 / 100, 1.0 / 200, 1.0 / 400, 1.0 / 800}) {
    dts.push_back(dt);
    drifts.push_back(drift(IntegratorType::Bdf2, dt));
    std::cout << "BDF2 torque-free body dt = " << dt << "  |dL|/|L| = " << drifts.back() << "\n";
  }
  real const order = FitOrder(dts, drifts);
  CAPTURE(order);
  // measured 7.0e-4, 1.75e-4, 4.4e-5, 1.1e-5: order 2.00
  REQUIRE(std::abs(order - 2) <= 0.1);
}

TEST_CASE("BDF2 restarts where the step size changes: free fall stays exact", "[scene][integrator]") {
  // Under constant gravity both integrators give a body's velocity exactly
  // v⁰ + g t when the history a step uses spans a step of its own size.
  // BDF2's equal-step coefficients after a step of another size hₚ would give
  // vⁿ + (hₚ/3 + 2h/3) g (off by 0.016 m/s at the first change here), so the
  // scene runs each change of size as backward Euler.
  IntegratorType const integrator = GENERATE(IntegratorType::BackwardEuler, IntegratorType::Bdf2);
  CAPTURE(ToString(integrator));
  SceneParams params;
  params.integrator = integrator;
  auto scene = MakeScene(params);
  RigidActorParams body;
  body.linearVelocity = Real3(1, 2, 0);
  RigidActor* actor = MakeRigid(*scene, body);
  real t = 0;
  for (real dt : {0.01, 0.01, 0.005, 0.005, 0.02, 0.02, 0.01, 0.01 * (1 + 1e-12)}) {
    CAPTURE(t, dt);
    StepOk(*scene, dt);
    t += dt;
    // Newton ends on a step of ~1e-16: the exact velocity to round-off
    REQUIRE((actor->GetLinearVelocity() - (body.linearVelocity + t * params.gravity)).norm() <= 1e-12);
  }
}

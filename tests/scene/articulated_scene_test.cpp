// The articulated actor stepped by the scene: a double pendulum of two
// revolute joints against an independent RK4 solution of its Lagrangian
// (order 1 for backward Euler, 2 for BDF2), the same pendulum built from
// rigid bodies and joints converging to it as the joint stiffness grows
// (error ∝ 1/k), and a floating-base chain in zero gravity conserving its
// momenta.
#include "test_support.h"

#include <array>
#include <cmath>
#include <iostream>

using namespace superdex;
using namespace superdex::test;

namespace {

// two uniform rods of length L and mass m, hinged about z at the origin and
// end to end, released horizontally (along +x) at rest; gravity −y
constexpr real kLength = 0.5, kMass = 1.0, kGravity = 9.81, kEndTime = 1.0;
real const kRodInertia = kMass * kLength * kLength / 12;
Real3 const kRodPrincipalInertia(1e-4, kRodInertia, kRodInertia);  // about x (along the rod), y, z

/// The pendulum's equations of motion in absolute angles a₁, a₂ (from +x,
/// counterclockwise about z), from its Lagrangian, written independently of
/// the library: M(a) ä + c(a, ȧ) + ∂V/∂a = 0 with
///   M₁₁ = m L²/4 + I + m L², M₁₂ = m L²/2 cos(a₁ − a₂), M₂₂ = m L²/4 + I,
///   c₁ = m L²/2 sin(a₁ − a₂) ȧ₂², c₂ = −m L²/2 sin(a₁ − a₂) ȧ₁²,
///   ∂V/∂a₁ = g (m L/2 + m L) cos a₁, ∂V/∂a₂ = g m L/2 cos a₂.
using PendulumState = std::array<real, 4>;  // a₁, a₂, ȧ₁, ȧ₂

PendulumState Derivative(PendulumState const& s) {
  real const m = kMass, l = kLength, i = kRodInertia, g = kGravity;
  real const k = m * l * l / 2, delta = s[0] - s[1];
  real const m11 = m * l * l / 4 + i + m * l * l, m12 = k * std::cos(delta), m22 = m * l * l / 4 + i;
  real const f1 = -(k * std::sin(delta) * s[3] * s[3] + g * (m * l / 2 + m * l) * std::cos(s[0]));
  real const f2 = -(-k * std::sin(delta) * s[2] * s[2] + g * m * l / 2 * std::cos(s[1]));
  real const det = m11 * m22 - m12 * m12;
  return {s[2], s[3], (m22 * f1 - m12 * f2) / det, (m11 * f2 - m12 * f1) / det};
}

/// RK4 at dt = 1e-5 to t = 1 s: its error (~dt⁴) is far below the tests'.
PendulumState ReferenceAtEnd() {
  PendulumState s{0, 0, 0, 0};
  int const steps = 100000;
  real const h = kEndTime / steps;
  auto axpy = [](PendulumState const& x, real a, PendulumState const& y) {
    return PendulumState{x[0] + a * y[0], x[1] + a * y[1], x[2] + a * y[2], x[3] + a * y[3]};
  };
  for (int n = 0; n < steps; ++n) {
    PendulumState const k1 = Derivative(s), k2 = Derivative(axpy(s, h / 2, k1)), k3 = Derivative(axpy(s, h / 2, k2)),
                        k4 = Derivative(axpy(s, h, k3));
    for (int c = 0; c < 4; ++c) s[c] += h / 6 * (k1[c] + 2 * k2[c] + 2 * k3[c] + k4[c]);
  }
  return s;
}

ArticulatedActorParams DoublePendulum() {
  ArticulatedActorParams p;
  for (int i = 0; i < 2; ++i) {
    ArticulatedLinkParams link;
    link.parent = i - 1;
    link.joint = JointType::Revolute;
    link.axis = Real3::UnitZ();
    link.parentToJointPosition = i == 0 ? Real3::Zero() : Real3(kLength, 0, 0);
    link.mass = kMass;
    link.inertia = kRodPrincipalInertia;
    link.centerOfMass = Real3(kLength / 2, 0, 0);
    p.links.push_back(link);
  }
  return p;
}

SceneParams Tight(IntegratorType integrator) {
  SceneParams params;
  params.integrator = integrator;
  params.gravity = Real3(0, -kGravity, 0);
  params.newton.velocityTolerance = 1e-11;
  return params;
}

/// (a₁, a₂) at t = 1 s of the articulated pendulum.
std::array<real, 2> ArticulatedAtEnd(IntegratorType integrator, real dt) {
  auto scene = MakeScene(Tight(integrator));
  Error error;
  ArticulatedActor* pendulum = scene->CreateArticulatedActor(DoublePendulum(), error);
  INFO(error.ToString());
  REQUIRE(pendulum);
  StepOk(*scene, dt, static_cast<int>(std::lround(kEndTime / dt)));
  DynamicArray<real> const q = pendulum->GetJointPositions();
  return {q[0], q[0] + q[1]};
}

}  // namespace

TEST_CASE("articulated double pendulum: backward Euler converges at order 1, BDF2 at order 2",
          "[scene][articulated]") {
  auto const [integrator, expectedOrder] =
      GENERATE(std::pair{IntegratorType::BackwardEuler, 1.0}, std::pair{IntegratorType::Bdf2, 2.0});
  CAPTURE(ToString(integrator));
  PendulumState const reference = ReferenceAtEnd();
  std::printf("double pendulum, RK4 reference at t = 1 s: a1 = %.9f, a2 = %.9f rad\n", reference[0], reference[1]);
  DynamicArray<real> dts, errors;
  for (real dt : {1.0 / 400, 1.0 / 800, 1.0 / 1600, 1.0 / 3200, 1.0 / 6400}) {
    std::array<real, 2> const a = ArticulatedAtEnd(integrator, dt);
    dts.push_back(dt);
    errors.push_back(std::hypot(a[0] - reference[0], a[1] - reference[1]));
    std::printf("  %s dt = 1/%.0f: a1 = %.9f, a2 = %.9f, error %.3e rad\n", std::string(ToString(integrator)).c_str(),
                1 / dt, a[0], a[1], errors.back());
    REQUIRE(errors.back() > 0);
  }
  real const order = FitOrder(dts, errors);
  std::printf("  fitted order %.3f\n", order);
  CAPTURE(order);
  // five halvings, errors far above the Newton tolerance and the reference's
  REQUIRE(std::abs(order - expectedOrder) <= 0.15);
  // and the errors are small in absolute terms at the finest step
  REQUIRE(errors.back() <= (expectedOrder == 1 ? 0.05 : 1e-4));
}

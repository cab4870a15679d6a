// The articulated actor stepped by the scene: a double pendulum of two
// revolute joints against an independent RK4 solution of its Lagrangian
// (order 1 for backward Euler, 2 for BDF2), the same pendulum built from
// rigid bodies and joints converging to it as the joint stiffness grows
// (error ∝ 1/k), and a floating-base chain in zero gravity conserving its
// momenta.
#include "test_scenes.h"

#include <array>
#include <cmath>
#include <iostream>
#include <numbers>

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

ArticulatedActorParams DoublePendulum() { return TwoRevoluteLinks(kLength, kMass); }

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
          "[long][scene][articulated]") {
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

TEST_CASE("articulated: the mass matrix (CRBA) and bias forces (RNEA) give the Lagrangian's accelerations",
          "[scene][articulated]") {
  // at a moving state of the pendulum, M(q)⁻¹(−bias) against the
  // independently written equations of motion
  auto scene = MakeScene(Tight(IntegratorType::Bdf2));
  Error error;
  ArticulatedActor* pendulum = scene->CreateArticulatedActor(DoublePendulum(), error);
  REQUIRE(pendulum);
  StepOk(*scene, 1e-3, 300);
  DynamicArray<real> const q = pendulum->GetJointPositions(), v = pendulum->GetJointVelocities();
  REQUIRE(std::abs(v[0]) + std::abs(v[1]) > 1);
  MatrixX const mass = pendulum->ComputeMassMatrix();
  VectorX const bias = pendulum->ComputeBiasForces(Real3(0, -kGravity, 0));
  VectorX const accel = mass.ldlt().solve(-bias);
  PendulumState const d = Derivative({q[0], q[0] + q[1], v[0], v[0] + v[1]});
  CAPTURE(accel.transpose(), d[2], d[3]);
  REQUIRE(std::abs(accel[0] - d[2]) <= 1e-10 * std::abs(d[2]));
  REQUIRE(std::abs(accel[0] + accel[1] - d[3]) <= 1e-10 * std::abs(d[3]));
}

TEST_CASE("the double pendulum built from rigid bodies and joints converges to the articulated one as 1/k",
          "[scene][articulated][rigid]") {
  // same links, same integrator: the rigid chain's joints (a pivot to the
  // world and a spherical joint, stiffness k) are the articulated actor's
  // revolute joints made compliant; the motion stays in the x–y plane
  real const dt = 1.0 / 400, endTime = 0.5;
  int const steps = static_cast<int>(std::lround(endTime / dt));
  auto articulatedScene = MakeScene(Tight(IntegratorType::BackwardEuler));
  Error error;
  ArticulatedActor* pendulum = articulatedScene->CreateArticulatedActor(DoublePendulum(), error);
  REQUIRE(pendulum);
  StepOk(*articulatedScene, dt, steps);
  DynamicArray<real> const q = pendulum->GetJointPositions();
  std::array<real, 2> const reference{q[0], q[0] + q[1]};
  std::printf("rigid vs articulated double pendulum, t = %.2f s, dt = 1/400, backward Euler:\n", endTime);
  DynamicArray<real> stiffnesses, errors;
  for (real k : {1e4, 1e5, 1e6, 1e7}) {
    auto scene = MakeScene(Tight(IntegratorType::BackwardEuler));
    std::array<RigidActor*, 2> bodies{};
    for (int i = 0; i < 2; ++i) {
      RigidActorParams body;
      body.mass = kMass;
      body.inertia = kRodPrincipalInertia;
      body.position = Real3((i + 0.5) * kLength, 0, 0);
      bodies[i] = MakeRigid(*scene, body);
    }
    RigidPivotPositionConstraintParams pin;
    pin.actor = bodies[0]->GetHandle();
    pin.localPos = Real3(-kLength / 2, 0, 0);
    pin.stiffness = k;
    REQUIRE(scene->CreateRigidPivotPositionConstraint(pin, error));
    RigidSphericalJointConstraintParams joint;
    joint.actorA = bodies[0]->GetHandle();
    joint.actorB = bodies[1]->GetHandle();
    joint.localPosA = Real3(kLength / 2, 0, 0);
    joint.localPosB = Real3(-kLength / 2, 0, 0);
    joint.stiffness = k;
    REQUIRE(scene->CreateRigidSphericalJointConstraint(joint, error));
    StepOk(*scene, dt, steps);
    real worst = 0;
    for (int i = 0; i < 2; ++i) {
      Real3 const axis = bodies[i]->GetRotation() * Real3::UnitX();
      worst = std::max(worst, std::abs(std::remainder(std::atan2(axis.y(), axis.x()) - reference[i], 2 * std::numbers::pi)));
      REQUIRE(std::abs(axis.z()) <= 1e-9);  // planar
    }
    stiffnesses.push_back(k);
    errors.push_back(worst);
    std::printf("  k = %.0e N/m: largest angle error %.3e rad\n", k, worst);
  }
  real const power = FitOrder(stiffnesses, errors);
  std::printf("  fitted power of k: %.3f\n", power);
  CAPTURE(power);
  // error ∝ 1/k over three decades
  REQUIRE(std::abs(power + 1) <= 0.1);
  REQUIRE(errors.back() <= 1e-4);
}

TEST_CASE("a floating-base chain in zero gravity keeps its momenta", "[scene][articulated]") {
  // a free root and four spherical joints, thrown spinning: linear momentum
  // is conserved to the Newton tolerance (round-off: ~1e-12); angular
  // momentum (about the origin) only loses what the integrator dissipates,
  // which halves with dt
  auto run = [](IntegratorType integrator, real dt, Real3& p0, Real3& p1, Real3& l0, Real3& l1) {
    SceneParams params = Tight(integrator);
    params.gravity = Real3::Zero();
    // the velocity-scaled step's round-off floor is ~2e-11 m/s here (rotations
    // composed through the chain at dt = 1/200)
    params.newton.velocityTolerance = 1e-9;
    auto scene = MakeScene(params);
    ArticulatedActorParams chain;
    for (int i = 0; i < 5; ++i) {
      ArticulatedLinkParams link;
      link.parent = i - 1;
      link.joint = i == 0 ? JointType::Free : JointType::Spherical;
      link.parentToJointPosition = i == 0 ? Real3(0.1, 0.2, 0) : Real3(0.2, 0, 0);
      link.mass = 1 + 0.2 * i;
      link.inertia = Real3(1e-3, 4e-3, 4e-3);
      link.centerOfMass = Real3(0.1, 0, 0);
      link.initialVelocity = i == 0 ? DynamicArray<real>{0.3, -0.1, 0.2, 0.5, 2.0, -1.0}
                                    : DynamicArray<real>{0.4 * i, -0.3, 0.8};
      chain.links.push_back(link);
    }
    Error error;
    ArticulatedActor* actor = scene->CreateArticulatedActor(chain, error);
    INFO(error.ToString());
    REQUIRE(actor);
    p0 = actor->GetLinearMomentum();
    l0 = actor->GetAngularMomentum();
    StepOk(*scene, dt, static_cast<int>(std::lround(1.0 / dt)));
    p1 = actor->GetLinearMomentum();
    l1 = actor->GetAngularMomentum();
  };
  Real3 p0, p1, l0, l1;
  DynamicArray<real> drift;
  for (real dt : {1.0 / 100, 1.0 / 200, 1.0 / 400}) {
    run(IntegratorType::BackwardEuler, dt, p0, p1, l0, l1);
    REQUIRE(p0.norm() > 1);
    REQUIRE((p1 - p0).norm() <= 1e-9 * p0.norm());
    drift.push_back((l1 - l0).norm() / l0.norm());
    std::printf("floating chain, backward Euler dt = 1/%.0f: |dp|/|p| = %.1e, |dL|/|L| = %.3e after 1 s\n", 1 / dt,
                (p1 - p0).norm() / p0.norm(), drift.back());
  }
  // backward Euler's dissipation is first order in dt
  REQUIRE(drift[0] / drift[1] > 1.7);
  REQUIRE(drift[1] / drift[2] > 1.7);
  DynamicArray<real> bdf2Drift;
  for (real dt : {1.0 / 200, 1.0 / 400}) {
    run(IntegratorType::Bdf2, dt, p0, p1, l0, l1);
    bdf2Drift.push_back((l1 - l0).norm() / l0.norm());
    std::printf("floating chain, BDF2 dt = 1/%.0f: |dp|/|p| = %.1e, |dL|/|L| = %.3e\n", 1 / dt,
                (p1 - p0).norm() / p0.norm(), bdf2Drift.back());
    REQUIRE((p1 - p0).norm() <= 1e-9 * p0.norm());
  }
  // BDF2's drift shrinks faster than first order (measured 3.0e-5 → 1.1e-5;
  // docs/articulated.md on what keeps it from 4×) and is ~100× below
  // backward Euler's at the same dt
  REQUIRE(bdf2Drift[0] / bdf2Drift[1] > 2.5);
  REQUIRE(bdf2Drift[1] < 0.02 * drift[2]);
}

namespace {
/// One link on a revolute (about z) or spherical joint at the origin, its
/// centre of mass 0.3 m along x: 1 kg, I_zz = 0.01 about it, so 0.1 kg m²
/// about the joint.
ArticulatedActor* SingleLink(Scene& scene, JointType joint) {
  ArticulatedActorParams p;
  ArticulatedLinkParams link;
  link.joint = joint;
  link.axis = Real3::UnitZ();
  link.mass = 1;
  link.inertia = Real3(0.005, 0.01, 0.01);
  link.centerOfMass = Real3(0.3, 0, 0);
  p.links.push_back(link);
  Error error;
  ArticulatedActor* actor = scene.CreateArticulatedActor(p, error);
  INFO(error.ToString());
  REQUIRE(actor);
  return actor;
}
}  // namespace

TEST_CASE("ArticulatedSingleDofTarget drives a revolute joint with the damped spring response", "[scene][articulated]") {
  // J θ̈ = −k (θ − θ̂) − d θ̇, J = 0.1 kg m², k = 10 N m/rad, d = 0.2 N m s/rad:
  // ω₀ = 10 rad/s, ζ = 0.1; from rest at 0 toward θ̂ = 0.5
  SceneParams params = Tight(IntegratorType::Bdf2);
  params.gravity = Real3::Zero();
  auto scene = MakeScene(params);
  ArticulatedActor* link = SingleLink(*scene, JointType::Revolute);
  ArticulatedSingleDofTargetConstraintParams drive;
  drive.actor = link->GetHandle();
  drive.target = 0.5;
  drive.stiffness = 10;
  drive.damping = 0.2;
  Error error;
  REQUIRE(scene->CreateArticulatedSingleDofTargetConstraint(drive, error));
  real const inertia = 0.01 + 1 * 0.3 * 0.3, omega0 = std::sqrt(10 / inertia), zeta = 0.2 / (2 * std::sqrt(10 * inertia));
  real const omegaD = omega0 * std::sqrt(1 - zeta * zeta);
  real worst = 0;
  real const dt = 1e-3;
  for (int step = 1; step <= 8000; ++step) {
    StepOk(*scene, dt);
    real const t = step * dt;
    real const exact = 0.5 - 0.5 * std::exp(-zeta * omega0 * t) *
                                 (std::cos(omegaD * t) + zeta / std::sqrt(1 - zeta * zeta) * std::sin(omegaD * t));
    worst = std::max(worst, std::abs(link->GetJointPositions()[0] - exact));
  }
  std::printf("single-DoF target: largest deviation from the damped spring over 8 s: %.2e rad (of 0.5)\n", worst);
  // BDF2 at ω₀ dt = 0.01 and the compliant damping's difference quotient
  // (first order in dt): measured 8.5e-4, asserted within 0.4 % of the step
  REQUIRE(worst <= 2e-3);
  // settled at the target (e^(−ζω₀ t) = 3e-4 at 8 s)
  REQUIRE(std::abs(link->GetJointPositions()[0] - 0.5) <= 1e-3);
}

TEST_CASE("ArticulatedSingleDofRange stops a falling link at its bound", "[scene][articulated]") {
  // a revolute pendulum released horizontally falls (θ decreases); the lower
  // bound −0.5 rad (k = 1e4 N m/rad, d = 20) holds it at −0.5 − m g r cos(0.5)/k
  auto scene = MakeScene(Tight(IntegratorType::BackwardEuler));
  ArticulatedActor* link = SingleLink(*scene, JointType::Revolute);
  ArticulatedSingleDofRangeConstraintParams range;
  range.actor = link->GetHandle();
  range.lowerLimit = -0.5;
  range.upperLimit = 0.5;
  range.stiffness = 1e4;
  range.damping = 20;
  Error error;
  Constraint* stop = scene->CreateArticulatedSingleDofRangeConstraint(range, error);
  REQUIRE(stop);
  REQUIRE(stop->RegisterQuery(QueryType::ConstraintForce, error));
  real lowest = 0;
  for (int step = 0; step < 400; ++step) {
    StepOk(*scene, 5e-3);
    lowest = std::min(lowest, link->GetJointPositions()[0]);
  }
  real const expected = -0.5 - 1 * kGravity * 0.3 * std::cos(0.5) / 1e4;
  real const theta = link->GetJointPositions()[0];
  std::printf("single-DoF range: lowest %.5f rad, at rest %.6f rad (expected %.6f)\n", lowest, theta, expected);
  REQUIRE(lowest >= -0.52);
  REQUIRE(std::abs(theta - expected) <= 1e-4);
  // the stop pushes back with the gravity torque
  Span<real const> const force = stop->GetForce(error);
  REQUIRE(std::abs(force[0] - kGravity * 0.3 * std::cos(0.5)) <= 1e-2);
}

TEST_CASE("the 3D rotation types drive and stop a spherical joint", "[scene][articulated]") {
  Error error;
  SECTION("Articulated3dRotationTarget settles at its target") {
    SceneParams params = Tight(IntegratorType::Bdf2);
    params.gravity = Real3::Zero();
    auto scene = MakeScene(params);
    ArticulatedActor* link = SingleLink(*scene, JointType::Spherical);
    Articulated3dRotationTargetConstraintParams drive;
    drive.actor = link->GetHandle();
    drive.targetFromCurrent = false;
    drive.rotation = Quat(Eigen::AngleAxis<real>(0.6, Real3(1, 1, 0).normalized()));
    drive.stiffness = 10;
    drive.damping = 1;
    Constraint* c = scene->CreateArticulated3dRotationTargetConstraint(drive, error);
    REQUIRE(c);
    DynamicArray<real> const g = c->GetDeviation();
    REQUIRE(std::abs(Real3(g[0], g[1], g[2]).norm() - 0.6) <= 1e-12);
    StepOk(*scene, 1e-2, 500);
    Real3 const remaining = Log(link->GetJointRotation(0) * drive.rotation.conjugate());
    std::printf("3D target: |Log(R_j R^-1)| = %.2e rad after 5 s\n", remaining.norm());
    REQUIRE(remaining.norm() <= 1e-4);
  }
  SECTION("Articulated3dRotationRange stops a falling spherical pendulum") {
    auto scene = MakeScene(Tight(IntegratorType::BackwardEuler));
    ArticulatedActor* link = SingleLink(*scene, JointType::Spherical);
    Articulated3dRotationRangeConstraintParams range;
    range.actor = link->GetHandle();
    range.lowerLimits = Real3(-1, -1, -0.5);
    range.upperLimits = Real3(1, 1, 0.5);
    range.stiffness = 1e4;
    range.damping = 20;
    REQUIRE(scene->CreateArticulated3dRotationRangeConstraint(range, error));
    real lowest = 0;
    for (int step = 0; step < 400; ++step) {
      StepOk(*scene, 5e-3);
      lowest = std::min(lowest, Log(link->GetJointRotation(0)).z());
    }
    Real3 const phi = Log(link->GetJointRotation(0));
    std::printf("3D range: lowest rotation-vector z %.5f, at rest (%.2e, %.2e, %.5f)\n", lowest, phi.x(), phi.y(), phi.z());
    REQUIRE(lowest >= -0.52);
    REQUIRE(std::abs(phi.z() + 0.5) <= 1e-3);
    REQUIRE(phi.head<2>().norm() <= 1e-6);
  }
}

TEST_CASE("the tree recursion steps the same trajectory as the dense block", "[scene][articulated][tree]") {
  // a branched tree with every joint type (a floating or a fixed base), joint
  // constraints on single joints (they add to the joints' diagonal blocks),
  // gravity, 0.5 s of BDF2 at dt = 1/100. Both solves take the same exact
  // Newton steps; they differ where the exact Hessian is indefinite (the
  // dense block's pivoted modified Cholesky, the tree's per-pivot one) and
  // by round-off, and both converge to the tight Newton tolerance below, so
  // the trajectories agree far below the integrator's error
  bool const floating = GENERATE(false, true);
  CAPTURE(floating);
  auto run = [&](ArticulatedBlockSolve solve, DynamicArray<real>& positions, SceneStats& stats) {
    SceneParams params = Tight(IntegratorType::Bdf2);
    params.newton.velocityTolerance = 1e-10;
    auto scene = MakeScene(params);
    ArticulatedActorParams const p = BranchedTree(floating, solve);
    Error error;
    ArticulatedActor* actor = scene->CreateArticulatedActor(p, error);
    INFO(error.ToString());
    REQUIRE(actor);
    ArticulatedSingleDofTargetConstraintParams target;
    target.actor = actor->GetHandle();
    target.jointIndex = 2;
    target.target = 0.3;
    target.stiffness = 50;
    target.damping = 0.5;
    REQUIRE(scene->CreateArticulatedSingleDofTargetConstraint(target, error));
    ArticulatedSingleDofRangeConstraintParams range;
    range.actor = actor->GetHandle();
    range.jointIndex = 3;
    range.lowerLimit = -0.02;
    range.upperLimit = 0.02;
    range.stiffness = 1e4;
    REQUIRE(scene->CreateArticulatedSingleDofRangeConstraint(range, error));
    Articulated3dRotationTargetConstraintParams drive;
    drive.actor = actor->GetHandle();
    drive.jointIndex = 1;
    drive.stiffness = 5;
    REQUIRE(scene->CreateArticulated3dRotationTargetConstraint(drive, error));
    StepOk(*scene, 1.0 / 100, 50);
    REQUIRE(actor->IsSolvedOnTree() == (solve == ArticulatedBlockSolve::Tree));
    positions = actor->GetJointPositions();
    stats = scene->GetStats();
  };
  DynamicArray<real> tree, dense;
  SceneStats treeStats, denseStats;
  run(ArticulatedBlockSolve::Tree, tree, treeStats);
  run(ArticulatedBlockSolve::Dense, dense, denseStats);
  real difference = 0, size = 0;
  for (std::size_t k = 0; k < tree.size(); ++k) {
    difference = std::max(difference, std::abs(tree[k] - dense[k]));
    size = std::max(size, std::abs(dense[k]));
  }
  std::printf("tree vs dense block (%s base): largest joint coordinate difference %.2e after 0.5 s\n",
              floating ? "floating" : "fixed", difference);
  REQUIRE(size > 0.1);
  CHECK(difference <= 1e-9);
  // the scene's matrix holds the joints' diagonal blocks only
  int const n = static_cast<int>(tree.size());
  CHECK(denseStats.hessianNonzeros == n * (n + 1) / 2);
  CHECK(treeStats.hessianNonzeros < 3 * n);
}

namespace {
/// The harness's chain-articulated: SphericalChain's joints with its 1 kg
/// links of 0.1 × 0.02 × 0.02 m
ArticulatedActorParams HorizontalChain(int links, ArticulatedBlockSolve solve) {
  ArticulatedActorParams p = SphericalChain(links, solve);
  for (ArticulatedLinkParams& link : p.links) {
    link.mass = 1;
    link.inertia = Real3(2 * 4e-4 / 12, (0.01 + 4e-4) / 12, (0.01 + 4e-4) / 12);
  }
  return p;
}
}  // namespace

TEST_CASE("a long chain released horizontally steps on the tree with its bounded pivot modification",
          "[scene][articulated][tree]") {
  // 100 spherical joints released horizontally (the harness's
  // chain-articulated): the exact Hessian is indefinite at the first Newton
  // iteration of every step, so the projected tree modifies pivots. Replacing
  // an indefinite pivot by its magnitude alone failed this chain in step 1
  // (pivots grew ~10³ per ten joints up the chain); bounded by the subtree's
  // inertia it converges as the dense block's modified Cholesky does, to
  // the same stage minima
  constexpr int kLinks = 100;
  auto run = [&](ArticulatedBlockSolve solve, DynamicArray<real>& positions, SceneStats& total) {
    SceneParams params;
    params.gravity = Real3(0, -9.81, 0);
    params.newton.velocityTolerance = 1e-10;
    auto scene = MakeScene(params);
    Error error;
    ArticulatedActor* actor = scene->CreateArticulatedActor(HorizontalChain(kLinks, solve), error);
    INFO(error.ToString());
    REQUIRE(actor);
    for (int step = 0; step < 10; ++step) {
      REQUIRE(scene->Step(1.0 / 60, error));
      SceneStats const& stats = scene->GetStats();
      total.newtonIterations += stats.newtonIterations;
      total.projectionFallbacks += stats.projectionFallbacks;
    }
    positions = actor->GetJointPositions();
  };
  DynamicArray<real> tree, dense;
  SceneStats treeStats, denseStats;
  run(ArticulatedBlockSolve::Tree, tree, treeStats);
  run(ArticulatedBlockSolve::Dense, dense, denseStats);
  real difference = 0;
  for (std::size_t k = 0; k < tree.size(); ++k) difference = std::max(difference, std::abs(tree[k] - dense[k]));
  std::printf("100-link chain, 10 steps of 1/60: tree %.1f Newton/step (%.1f projected retries), dense %.1f "
              "(%.1f); largest joint coordinate difference %.2e\n",
              treeStats.newtonIterations / 10.0, treeStats.projectionFallbacks / 10.0,
              denseStats.newtonIterations / 10.0, denseStats.projectionFallbacks / 10.0, difference);
  // the exact Hessian is indefinite in every step: the dense block goes
  // through the scene's projected retry, the tree modifies its pivots at
  // once without re-assembling the scene
  CHECK(denseStats.projectionFallbacks >= 10);
  CHECK(treeStats.projectionFallbacks == 0);
  CHECK(treeStats.newtonIterations <= denseStats.newtonIterations + 5);
  CHECK(difference <= 1e-9);
}

TEST_CASE("a 500-link chain released horizontally falls for a second at dt = 1/60 on the tree",
          "[long][scene][articulated][tree]") {
  // The harness's chain-articulated N = 500. After the first modified pivot
  // the directions a spherical joint does not eliminate (its translations)
  // can grow up the chain (~3 % per joint in step 13, pivots from 1e9 to
  // 1e17, where round-off failed the modified factorization and the step);
  // the Gauss–Newton Hessian then takes over for that iteration
  // (ArticulatedActor::FactorizeOwnBlock). Whether that happens depends on
  // round-off; the second of falling must step either way, converging as
  // the chain does (3.7 Newton iterations per step measured)
  constexpr int kLinks = 500, kSteps = 60;
  SceneParams params;
  params.gravity = Real3(0, -9.81, 0);
  auto scene = MakeScene(params);
  Error error;
  ArticulatedActor* actor = scene->CreateArticulatedActor(HorizontalChain(kLinks, ArticulatedBlockSolve::Tree), error);
  REQUIRE(actor);
  // mechanical energy: kinetic + m g y of every link's centre of mass
  auto energy = [&] {
    real e = actor->GetKineticEnergy();
    for (int i = 0; i < kLinks; ++i) e += actor->GetLinkMass(i) * 9.81 * actor->GetLinkCenterOfMass(i).y();
    return e;
  };
  real const startEnergy = energy();
  long newton = 0;
  for (int step = 0; step < kSteps; ++step) {
    INFO("step " << step);
    REQUIRE(scene->Step(1.0 / 60, error));
    newton += scene->GetStats().newtonIterations;
  }
  std::printf("500-link chain, %d steps of 1/60: %.2f Newton/step, %ld modified and %ld Gauss-Newton tree "
              "factorizations\n",
              kSteps, double(newton) / kSteps, actor->GetNumModifiedTreeFactorizations(),
              actor->GetNumGaussNewtonTreeFactorizations());
  CHECK(newton <= 5 * kSteps);
  // it fell: the tip is below its start. Backward Euler only dissipates: the
  // energy cannot have grown (round-off: 1e-9 of the 500 kg · 9.81 · 25 m
  // scale), and a second of falling turned much of it into kinetic energy
  // and dissipation (a drop of the centre of mass of over 1 m)
  CHECK(actor->GetLinkPosition(kLinks - 1).y() < -1);
  real const endEnergy = energy();
  real const scale = kLinks * 9.81 * kLinks * 0.1 / 2;
  CAPTURE(startEnergy, endEnergy, actor->GetKineticEnergy());
  CHECK(endEnergy <= startEnergy + 1e-9 * scale);
  CHECK(actor->GetKineticEnergy() >= 0.01 * scale);
}

TEST_CASE("Newton's first iterate extrapolated at the last acceleration converges to the same states in fewer "
          "iterations",
          "[scene][articulated][tree]") {
  // the harness's 50-link chain falling from horizontal for 60 steps of 1/60
  // (smooth motion): from the constant-velocity prediction Newton takes 4.67
  // iterations per step, from the extrapolated velocity 4.12 (measured; 4.05
  // and 3.40 at the harness's tolerance of 1e-6 m/s). The
  // states agree to the Newton tolerance: each stage stops once its step is
  // below 1e-10 m/s, so two stage solutions differ by ~1e-12 m per step; the
  // joints of a chain that folds over 60 steps amplify such differences by
  // well under 1e3, hence 1e-8.
  constexpr int kLinks = 50, kSteps = 60;
  auto run = [&](bool extrapolate, DynamicArray<real>& positions) {
    SceneParams params;
    params.gravity = Real3(0, -9.81, 0);
    params.newton.velocityTolerance = 1e-10;
    auto scene = MakeScene(params);
    Error error;
    ArticulatedActorParams p = HorizontalChain(kLinks, ArticulatedBlockSolve::Tree);
    p.extrapolateFirstIterate = extrapolate;
    ArticulatedActor* actor = scene->CreateArticulatedActor(p, error);
    REQUIRE(actor);
    long newton = 0;
    for (int step = 0; step < kSteps; ++step) {
      INFO("step " << step << ": " << error.ToString());
      REQUIRE(scene->Step(1.0 / 60, error));
      newton += scene->GetStats().newtonIterations;
    }
    positions = actor->GetJointPositions();
    return newton;
  };
  DynamicArray<real> predicted, extrapolated;
  long const fromPrediction = run(false, predicted);
  long const fromExtrapolation = run(true, extrapolated);
  real difference = 0;
  for (std::size_t k = 0; k < predicted.size(); ++k)
    difference = std::max(difference, std::abs(predicted[k] - extrapolated[k]));
  std::printf("50-link chain, %d steps of 1/60 (tolerance 1e-10 m/s): %.2f Newton/step from the prediction, "
              "%.2f extrapolated; largest joint coordinate difference %.2e\n",
              kSteps, double(fromPrediction) / kSteps, double(fromExtrapolation) / kSteps, difference);
  CHECK(fromExtrapolation + kSteps / 3 <= fromPrediction);
  CHECK(difference <= 1e-8);
}

TEST_CASE("a step after a much shorter one starts from the prediction", "[scene][articulated][tree]") {
  // an arm (a revolute joint, then a spherical one) steps 0.01, 1e-15, 0.01:
  // the 1e-15 step leaves round-off / 1e-15 in the joint velocity, and
  // extrapolating it by h/hₚ = 1e13 failed the third step in 50 Newton
  // iterations (also with sub-steps). The third step starts from the
  // prediction, as with extrapolation off: the same iterations, the same
  // state bit for bit
  auto run = [](bool extrapolate, int maxSubsteps, DynamicArray<real>& positions) {
    SceneParams params;
    params.substeps.maxSubsteps = maxSubsteps;
    auto scene = MakeScene(params);
    Error error;
    ArticulatedActorParams p;
    p.links.resize(2);
    p.links[0].parent = -1;
    p.links[0].joint = JointType::Revolute;
    p.links[0].axis = Real3(0, 0, 1);
    p.links[0].parentToJointPosition = Real3(0, 4, 0);
    p.links[0].centerOfMass = Real3(0.25, 0, 0);
    p.links[1].parent = 0;
    p.links[1].joint = JointType::Spherical;
    p.links[1].parentToJointPosition = Real3(0.5, 0, 0);
    p.links[1].centerOfMass = Real3(0.25, 0, 0);
    p.extrapolateFirstIterate = extrapolate;
    ArticulatedActor* arm = scene->CreateArticulatedActor(p, error);
    REQUIRE(arm);
    for (real dt : {0.01, 1e-15, 0.01}) {
      INFO("dt " << dt << ": " << error.ToString());
      REQUIRE(scene->Step(dt, error));
    }
    positions = arm->GetJointPositions();
    return scene->GetStats().newtonIterations;
  };
  for (int maxSubsteps : {1, 8}) {
    CAPTURE(maxSubsteps);
    DynamicArray<real> extrapolated, predicted;
    int const iterations = run(true, maxSubsteps, extrapolated);
    CHECK(iterations == run(false, maxSubsteps, predicted));
    CHECK(iterations <= 4);
    CHECK(extrapolated == predicted);
  }
}

TEST_CASE("a dense block above kDenseSolverMaxUnknowns is refused, on every path to it",
          "[scene][articulated][errors]") {
  // 1,700 spherical joints: 5,100 DoFs. ArticulatedBlockSolve::Dense ran for
  // minutes per step (800 links: 3.1 s); it is refused at creation. On the
  // tree, a constraint closing the chain's two ends (two joints reached: the
  // dense block) is refused by the step, which changes nothing
  constexpr int kLinks = 1700;
  Error error;
  auto scene = MakeScene();
  REQUIRE_FALSE(scene->CreateArticulatedActor(HorizontalChain(kLinks, ArticulatedBlockSolve::Dense), error));
  CHECK(error.GetCode() == ErrorCode::InvalidArgument);
  CHECK(error.GetMessage() ==
        "ArticulatedActorParams.blockSolve = Dense takes at most kDenseSolverMaxUnknowns = 5000 DoFs (the dense "
        "block is factorized in O(n³) every Newton iteration), got 5100 DoFs; use Tree");
  CHECK(scene->GetNumActors() == 0);

  auto treeScene = MakeScene();
  ArticulatedActor* chain =
      treeScene->CreateArticulatedActor(HorizontalChain(kLinks, ArticulatedBlockSolve::Tree), error);
  REQUIRE(chain);
  RigidSphericalJointConstraintParams close;
  close.actorA = close.actorB = chain->GetHandle();
  close.linkA = 0;
  close.linkB = kLinks - 1;
  close.stiffness = 1e3;
  REQUIRE(treeScene->CreateRigidSphericalJointConstraint(close, error));
  DynamicArray<real> const before = chain->GetJointPositions();
  REQUIRE_FALSE(treeScene->Step(0.01, error));
  CHECK(error.GetCode() == ErrorCode::InvalidArgument);
  CHECK(Contains(error.GetMessage(), "a dense block of 5100 DoFs (an articulated actor's, where it cannot solve on "
                                     "its tree"));
  CHECK(Contains(error.GetMessage(), "is above kDenseSolverMaxUnknowns = 5000 DoFs in the scene's matrix"));
  CHECK(chain->GetJointPositions() == before);
  CHECK(treeScene->GetTime() == 0);
}

TEST_CASE("a tree with no positive definite modification fails the step and changes nothing",
          "[scene][articulated][tree]") {
  // dt = 1e300: the inertia weight 1/dt² underflows to zero, and a horizontal
  // link on a revolute joint has a gravity torque but no curvature, so the
  // Newton matrix is the 1×1 zero: neither exact nor modified (its floor is
  // 1e-10 of a zero diagonal) positive definite
  SceneParams params;
  params.gravity = Real3(0, -9.81, 0);
  auto scene = MakeScene(params);
  ArticulatedActorParams p;
  ArticulatedLinkParams link;
  link.joint = JointType::Revolute;
  link.axis = Real3::UnitZ();
  link.centerOfMass = Real3(0.5, 0, 0);
  p.links.push_back(link);
  Error error;
  ArticulatedActor* actor = scene->CreateArticulatedActor(p, error);
  REQUIRE(actor);
  DynamicArray<real> const before = actor->GetJointPositions();
  REQUIRE_FALSE(scene->Step(1e300, error));
  CAPTURE(error.ToString());
  CHECK(error.GetCode() == ErrorCode::LinearSolverFailed);
  CHECK(error.GetMessage().find("no positive definite modification") != std::string::npos);
  CHECK(actor->GetJointPositions() == before);
  CHECK(scene->GetTime() == 0);
  StepOk(*scene, 1.0 / 60, 1);  // the scene steps on
}

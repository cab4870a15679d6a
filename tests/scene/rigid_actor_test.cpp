// The rigid body's stage inertia term (actors/rigid_actor.h) and what it
// implies for whole steps:
//
// (a) the gradient against central differences of Actor::Energy, and at the
//     stage's stationary point the Gauss–Newton Hessian against the
//     finite-difference Jacobian of the gradient (the dropped term multiplies
//     φ − φ̂, which vanishes there);
// (b) a torque-free body spinning about a non-principal axis keeps its
//     angular-momentum vector (backward Euler with the momentum-conserving
//     rotation target) and does not gain kinetic energy;
// (c) free fall reproduces backward Euler's discrete solution to round-off.
#include "test_support.h"
#include "white_box.h"


#include <limits>
#include <numbers>
#include <type_traits>

using namespace superdex;
using namespace superdex::test;
using internal::ActorTestAccess;

namespace {

constexpr real kPi = std::numbers::pi_v<real>;
constexpr real kStep = 1e-2;  // h
Real3 const kGravity{0, -9.81, 0};

// Energies here are up to ~1e4 (w = 1/h² = 1e4) and gradients up to ~2e4.
// Step 1e-6: round-off ulp(E)/ε ~ 2e-9·|E| ~ 1e-5 absolute, i.e. ~1e-9
// relative to the gradient; truncation ε²/6·|E'''| is smaller still. The
// gradient and the Hessian must match to 1e-6 relative.
constexpr real kFdStep = 1e-6;
constexpr real kDerivativeTol = 1e-6;

std::unique_ptr<RigidActor> MakeSpinningBody() {
  RigidActorParams params;
  params.mass = 1.7;
  params.inertia = Real3(0.3, 0.5, 0.8);
  params.position = Real3(0.1, -0.2, 0.3);
  params.rotation = Quat(Eigen::AngleAxis<real>(1.2, Real3(1, 2, -1).normalized()));
  params.linearVelocity = Real3(0.4, -0.3, 1.1);
  params.angularVelocity = Real3(2.0, -1.5, 0.7);  // world frame
  Error error;
  auto body = RigidActor::Create(params, error);
  INFO(error.ToString());
  REQUIRE(body);
  return body;
}

/// A one-actor assembler with the natural ordering.
internal::HessianAssembler MakeAssembler(RigidActor const& body) {
  DynamicArray<int> blockSizes;
  DynamicArray<DynamicArray<int>> contributors;
  ActorTestAccess::AppendDofBlockSizes(body, blockSizes);
  ActorTestAccess::AppendContributorDofs(body, contributors);
  REQUIRE(contributors.size() == 1);
  REQUIRE(contributors[0] == DynamicArray<int>{0, 1, 2, 3, 4, 5});
  internal::HessianAssembler assembler;
  Error error;
  bool const ok = assembler.Analyze(RigidActor::kNumDofs, blockSizes, contributors,
                                    OrderingMethod::Natural, error);
  INFO(error.ToString());
  REQUIRE(ok);
  return assembler;
}

/// The assembled gradient (and, if asked, the dense Hessian) at the body's
/// current configuration.
VectorX Gradient(RigidActor const& body, internal::HessianAssembler& assembler,
                 MatrixX* hessian = nullptr) {
  VectorX gradient = VectorX::Zero(RigidActor::kNumDofs);
  assembler.ZeroValues();
  ActorTestAccess::AddGradientAndHessian(body, Span<real>(gradient.data(), gradient.size()),
                                         assembler, 0);
  if (hessian) *hessian = DenseNaturalHessian(assembler);
  return gradient;
}

/// Central differences of f() over the body's six DoFs (columns).
template <class F>
MatrixX CentralDifference(RigidActor& body, F const& f) {
  Real3 const position = body.GetPosition();
  Quat const rotation = body.GetRotation();
  MatrixX result;
  for (int dof = 0; dof < RigidActor::kNumDofs; ++dof) {
    SetPerturbedPose(body, position, rotation, dof, +kFdStep);
    auto const plus = f();
    SetPerturbedPose(body, position, rotation, dof, -kFdStep);
    auto const minus = f();
    if constexpr (std::is_arithmetic_v<std::decay_t<decltype(plus)>>) {
      if (dof == 0) result.resize(1, RigidActor::kNumDofs);
      result(0, dof) = (plus - minus) / (2 * kFdStep);
    } else {
      if (dof == 0) result.resize(plus.size(), RigidActor::kNumDofs);
      result.col(dof) = (plus - minus) / (2 * kFdStep);
    }
  }
  Error error;
  REQUIRE(body.SetPose(position, rotation, error));
  return result;
}

}  // namespace

TEST_CASE("rigid inertia gradient matches central differences of the stage energy",
          "[scene][rigid][derivatives]") {
  // body-frame stage rotation φ = Log(Rⁿᵀ R): tiny, moderate, near π
  real const angle = GENERATE(0.0, 1e-7, 0.3, 1.7, kPi - 1e-3);
  CAPTURE(angle);
  auto body = MakeSpinningBody();
  Real3 const startPosition = body->GetPosition();
  Quat const startRotation = body->GetRotation();
  ActorTestAccess::BeginStage(*body, internal::MakeStage(IntegratorType::BackwardEuler, kStep, false),
                              kGravity);

  // an iterate away from the stage's stationary point
  Quat const stageRotation(Eigen::AngleAxis<real>(angle, Real3(-0.3, 0.8, 0.5).normalized()));
  Error error;
  REQUIRE(body->SetPose(startPosition + Real3(0.03, -0.05, 0.02), startRotation * stageRotation,
                        error));

  internal::HessianAssembler assembler = MakeAssembler(*body);
  VectorX const gradient = Gradient(*body, assembler);
  MatrixX const fd = CentralDifference(*body, [&] { return ActorTestAccess::Energy(*body); });
  VectorX const fdGradient = fd.row(0).transpose();
  CAPTURE(gradient.transpose(), fdGradient.transpose());
  REQUIRE(gradient.head<3>().norm() > 1);
  REQUIRE(gradient.tail<3>().norm() > 1);  // φ̂ ≠ 0: the rotation gradient is never trivially 0
  real const mismatch = MaxScaledError(gradient, fdGradient);
  CAPTURE(mismatch);
  REQUIRE(mismatch <= kDerivativeTol);
}

TEST_CASE("at the stage's stationary point the rigid Hessian is the Jacobian of the gradient",
          "[scene][rigid][derivatives]") {
  auto body = MakeSpinningBody();
  Real3 const startPosition = body->GetPosition();
  Quat const startRotation = body->GetRotation();
  Real3 const startVelocity = body->GetLinearVelocity();
  Real3 const startBodyOmega = startRotation.conjugate() * body->GetAngularVelocity();
  ActorTestAccess::BeginStage(*body, internal::MakeStage(IntegratorType::BackwardEuler, kStep, false),
                              kGravity);
  internal::HessianAssembler assembler = MakeAssembler(*body);

  // reach the stationary point by Newton on the actor's own gradient (checked
  // above) and Hessian: the residual φ − φ̂ vanishes there, so Gauss–Newton
  // converges quadratically
  Error error;
  VectorX gradient;
  MatrixX hessian;
  for (int iteration = 0; iteration < 20; ++iteration) {
    gradient = Gradient(*body, assembler, &hessian);
    VectorX const step = hessian.ldlt().solve(-gradient);
    Real3 const dt = step.head<3>(), dr = step.tail<3>();
    REQUIRE(body->SetPose(body->GetPosition() + dt, Exp(dr) * body->GetRotation(), error));
  }
  gradient = Gradient(*body, assembler, &hessian);
  CAPTURE(gradient.transpose());
  real const scale = hessian.cwiseAbs().maxCoeff();
  REQUIRE(gradient.norm() <= 1e-12 * scale);

  // it is backward Euler's step: t* = tⁿ + h vⁿ + h² g, and the rotation
  // keeps the angular momentum, Exp(φ) I φ/h = I Ωⁿ (body frame at tⁿ)
  Real3 const expectedPosition = startPosition + kStep * startVelocity + kStep * kStep * kGravity;
  REQUIRE((body->GetPosition() - expectedPosition).norm() <= 1e-14);
  Real3 const phi = Log(startRotation.conjugate() * body->GetRotation());
  Real3 const inertia = body->GetInertia();
  Real3 const momentumAfter = Exp(phi) * (inertia.asDiagonal() * phi / kStep);
  Real3 const momentumBefore = inertia.asDiagonal() * startBodyOmega;
  CAPTURE(momentumAfter.transpose(), momentumBefore.transpose());
  REQUIRE((momentumAfter - momentumBefore).norm() <= 1e-12 * momentumBefore.norm());
  // (and the rotation is not trivial: the body turns by |hΩ| ≈ 0.026 rad)
  REQUIRE(phi.norm() > 0.02);

  // the Hessian there against the finite-difference Jacobian of the gradient
  MatrixX const fd = CentralDifference(*body, [&] { return Gradient(*body, assembler); });
  CAPTURE(hessian, fd);
  real const mismatch = MaxScaledError(hessian, fd);
  CAPTURE(mismatch);
  REQUIRE(mismatch <= kDerivativeTol);
  // the rotation block is a full (non-diagonal) matrix: R I Rᵀ in the world
  REQUIRE(std::abs(hessian(3, 4)) > 1);
  REQUIRE(SymmetricEigenvalues(hessian).minCoeff() > 0);
}

TEST_CASE("a torque-free body keeps its angular momentum vector and does not gain energy",
          "[scene][rigid]") {
  SceneParams params;
  params.gravity = Real3::Zero();
  params.integrator = IntegratorType::BackwardEuler;
  params.newton.velocityTolerance = 1e-12;
  auto scene = MakeScene(params);
  RigidActorParams body;
  body.inertia = Real3(1, 2, 3);
  body.rotation = Quat(Eigen::AngleAxis<real>(0.7, Real3(1, 1, 0).normalized()));
  // body-frame Ω = (1, 0.5, -0.7) (Eigen-rotated into the world): not along
  // a principal axis, so the body tumbles
  Real3 const bodyOmega(1.0, 0.5, -0.7);
  body.angularVelocity = body.rotation * bodyOmega;
  RigidActor* actor = MakeRigid(*scene, body);

  Real3 const momentum = actor->GetAngularMomentum();
  real const initialEnergy = actor->GetKineticEnergy();
  REQUIRE(momentum.norm() > 1);
  // non-principal: L is not parallel to ω
  REQUIRE(momentum.normalized().cross(actor->GetAngularVelocity().normalized()).norm() > 0.1);

  // Newton stops when its step is <= 1e-12 rad/s·h: the momentum error a step
  // leaves is ~|I|·1e-12 rad/s, so 1000 steps stay well inside 1e-9 relative.
  // The kinetic energy cannot increase (E(Mⁿ) ≥ E(Mⁿ⁺¹) + Ωⁿ⁺¹·(Mⁿ − Mⁿ⁺¹),
  // and Mⁿ is Mⁿ⁺¹ rotated about Ωⁿ⁺¹); each step may show the same 1e-12
  // relative Newton error.
  real worstMomentum = 0, previousEnergy = initialEnergy;
  real const omega0 = actor->GetAngularVelocity().norm();
  for (int step = 1; step <= 1000; ++step) {
    StepOk(*scene, kStep);
    real const momentumError = (actor->GetAngularMomentum() - momentum).norm() / momentum.norm();
    real const energy = actor->GetKineticEnergy();
    CAPTURE(step, momentumError, energy, previousEnergy);
    REQUIRE(momentumError <= 1e-9);
    REQUIRE(energy <= previousEnergy * (1 + 1e-12));
    worstMomentum = std::max(worstMomentum, momentumError);
    previousEnergy = energy;
  }
  CAPTURE(worstMomentum, initialEnergy, previousEnergy, omega0);
  // the body really turned (many revolutions) and backward Euler dissipated
  REQUIRE(scene->GetTime() > 9.99);
  REQUIRE(previousEnergy < initialEnergy);
  // the centre of mass did not move
  REQUIRE(actor->GetPosition().norm() <= 1e-15);
}

TEST_CASE("free fall is backward Euler's discrete solution to round-off", "[scene][rigid]") {
  SceneParams params;
  params.gravity = kGravity;
  params.integrator = IntegratorType::BackwardEuler;
  params.newton.velocityTolerance = 1e-12;
  auto scene = MakeScene(params);
  RigidActor* actor = MakeRigid(*scene, RigidActorParams{});
  real const g = 9.81;

  // v_n = −n g h, y_n = −g h² n(n+1)/2, to round-off. Each step rounds y at
  // ~ulp(y_k) <= ε|y_k|, and v = (yᵏ⁺¹ − yᵏ)/h carries that error into the
  // next step's target h v: summed over k <= n, |Δv_n| <= Σ ε|y_k|/h ≈
  // ε g h n³/6 = (ε n²/6)|v_n|, and the same order for y. The bound below,
  // 4ε(n+1)², is that model with a factor ~24 of margin (measured: 7e-13
  // relative at n = 500 against a bound of 2e-10; ~1e-16 for n <= 5).
  auto roundOffBound = [](int n) {
    return 4 * std::numeric_limits<real>::epsilon() * (n + 1) * (n + 1);
  };
  real worstY = 0, worstV = 0;
  for (int n = 1; n <= 500; ++n) {
    StepOk(*scene, kStep);
    real const y = -g * kStep * kStep * n * (n + 1) / 2;
    real const v = -n * g * kStep;
    Real3 const position = actor->GetPosition();
    Real3 const velocity = actor->GetLinearVelocity();
    real const errorY = std::abs(position.y() - y) / std::abs(y);
    real const errorV = std::abs(velocity.y() - v) / std::abs(v);
    CAPTURE(n, position.transpose(), y, velocity.transpose(), v, errorY, errorV);
    REQUIRE(errorY <= roundOffBound(n));
    REQUIRE(errorV <= roundOffBound(n));
    // nothing acts across or about the fall
    REQUIRE(std::abs(position.x()) + std::abs(position.z()) <= 1e-15);
    REQUIRE(std::abs(velocity.x()) + std::abs(velocity.z()) <= 1e-15);
    REQUIRE(actor->GetAngularVelocity().norm() <= 1e-15);
    worstY = std::max(worstY, errorY);
    worstV = std::max(worstV, errorV);
  }
  CAPTURE(worstY, worstV);
  REQUIRE((actor->GetRotation().coeffs() - Quat::Identity().coeffs()).norm() <= 1e-15);
}

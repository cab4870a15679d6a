// The compliant potential shared by every constraint type
// (constraints/compliant_potential.h, constraints.md "Incremental potential",
// "Saturation", "Gradient and approximate Hessian"):
//
//   Φᶜ = U(‖g‖) + d/(2h) ‖Δg‖²,  Δg = g(q, p̂) − g(q⁰, p̂⁰)
//   rᶜ = Jᵀ (κ g + d/h Δg),      Kᶜ ≈ (κ + d/h) JᵀJ
//
// (a) rᶜ, as the stage solver assembles it, against central differences of
//     Φᶜ along every DoF, with damping, a stage-start value taken at another
//     configuration and a moved target;
// (b) saturation: the ramp ρ, κ and the force cap, at and around g = 0 and ḡ;
// (c) the Gauss–Newton Hessian: symmetric PSD, and equal to the
//     finite-difference Jacobian of rᶜ where g = g⁰ = 0;
// (d) the range rule;
// (e) the constraint Hessian choices: Gauss–Newton, with geometric stiffness
//     (exact, and its diagonal form in projected iterations) and the
//     diagonal form throughout, the same gradient.
#include "constraint_test_util.h"


#include <limits>
#include <numbers>

using namespace superdex;
using namespace superdex::test;
using internal::CompliantParams;

namespace {

constexpr real kEps = std::numeric_limits<real>::epsilon();
constexpr real kStageDuration = 1e-2;  // h

// Φᶜ is O(10) with gradients O(100) here. Step 1e-6: round-off
// ulp(Φᶜ)/ε ~ 2e-9, truncation ε²/6·|Φᶜ'''| ~ 1e-10; measured ~1e-9 absolute,
// ~1e-11 relative. The residual must match to 1e-6 relative.
constexpr real kFdStep = 1e-6;
constexpr real kResidualTol = 1e-6;

enum class Type { SphericalJoint, PivotPosition };

char const* Name(Type type) {
  return type == Type::SphericalJoint ? "RigidSphericalJoint" : "RigidPivotPosition";
}

Constraint* MakeConstraint(Type type, RigidPair& pair, CompliantParams const& compliance) {
  return type == Type::SphericalJoint ? MakeSphericalJoint(pair, compliance)
                                       : MakePivotPosition(pair, compliance);
}

/// A workspace sized for `c`.
internal::TermWorkspace SizedWorkspace(Constraint const& c) {
  internal::TermWorkspace ws;
  ws.Reserve(c.GetDimension(), c.GetNumDofs());
  return ws;
}

/// A 1-contributor assembler over the scene's DoFs for constraint `c`, with
/// the natural ordering.
internal::HessianAssembler MakeAssembler(Scene const& scene, Constraint const& c) {
  internal::HessianAssembler assembler;
  DynamicArray<int> blockSizes(scene.GetNumActors(), RigidActor::kNumDofs);
  DynamicArray<DynamicArray<int>> contributors{ConstraintTestAccess::Dofs(c)};
  Error error;
  bool const ok = assembler.Analyze(scene.GetNumDofs(), blockSizes, contributors,
                                    OrderingMethod::Natural, error);
  INFO(error.ToString());
  REQUIRE(ok);
  return assembler;
}

/// rᶜ in DoF-list order as the stage solver assembles it (and, in
/// `hessian` if given, the assembled Hessian restricted to those DoFs).
VectorX Residual(Constraint const& c, internal::HessianAssembler& assembler,
                 internal::TermWorkspace& ws, MatrixX* hessian = nullptr,
                 ConstraintHessian mode = ConstraintHessian::GaussNewton, bool project = true) {
  VectorX gradient = VectorX::Zero(assembler.GetNumDofs());
  assembler.ZeroValues();
  ConstraintTestAccess::AddGradientAndHessian(c, kStageDuration,
                                              Span<real>(gradient.data(), gradient.size()),
                                              assembler, 0, ws, mode, project);
  DynamicArray<int> const& dofs = ConstraintTestAccess::Dofs(c);
  int const n = static_cast<int>(dofs.size());
  VectorX local(n);
  for (int i = 0; i < n; ++i) local[i] = gradient[dofs[i]];
  // nothing lands outside the constraint's DoFs
  VectorX outside = gradient;
  for (int dof : dofs) outside[dof] = 0;
  REQUIRE(outside.isZero(0));
  if (hessian) {
    MatrixX const full = DenseNaturalHessian(assembler);
    hessian->resize(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) (*hessian)(i, j) = full(dofs[i], dofs[j]);
  }
  return local;
}

/// ρ(x) and ρ'(x) of constraints.md, written independently of the library:
/// ρ = x²/ḡ − x³/(3ḡ²) below ḡ, x − ḡ/3 above; ρ' = 2x/ḡ − x²/ḡ² below, 1 above.
real Ramp(real x, real s) { return x < s ? x * x / s - x * x * x / (3 * s * s) : x - s / 3; }
real RampDerivative(real x, real s) { return x < s ? 2 * x / s - x * x / (s * s) : 1; }

}  // namespace

// ---------------------------------------------------------------------------
// (a) the residual is the gradient of Φᶜ
// ---------------------------------------------------------------------------

TEST_CASE("compliant residual matches central differences of the incremental potential",
          "[constraints][compliant][derivatives]") {
  Type const type = GENERATE(Type::SphericalJoint, Type::PivotPosition);
  // saturation off, on with ‖g‖ below ḡ, on with ‖g‖ above ḡ
  real const saturation = GENERATE(-1.0, 5.0, 0.05);
  CAPTURE(Name(type), saturation);
  CompliantParams const compliance{.stiffness = 150, .damping = 4, .saturation = saturation};
  real const h = kStageDuration;

  // stage start configuration q⁰
  Pose const startA = RandomPose(0.6, 21), startB = RandomPose(2.4, 22);
  RigidPair pair = MakeRigidPair(startA, startB);
  Constraint* c = MakeConstraint(type, pair, compliance);
  internal::TermWorkspace ws = SizedWorkspace(*c);

  // between steps the target moves (no UpdateOldTarget): the stage start
  // value differences against the old target p̂⁰ = kTargetPosition
  bool const hasTarget = type == Type::PivotPosition;
  VectorX const gStartExpected = Deviation(*c);  // g(q⁰, p̂⁰)
  Error error;
  if (hasTarget) REQUIRE(c->SetTargetPosition(kTargetPosition + Real3(0.05, -0.03, 0.02), error));
  ConstraintTestAccess::BeginStage(*c, ws);
  VectorX const gStart = ConstraintTestAccess::StageStartValue(*c);
  CAPTURE(gStart.transpose());
  REQUIRE(gStart == gStartExpected);
  if (hasTarget) REQUIRE_FALSE(gStart == Deviation(*c));  // the target difference is present

  // and moves again within the stage; the bodies move to q
  if (hasTarget) REQUIRE(c->SetTargetPosition(kTargetPosition + Real3(-0.04, 0.06, 0.03), error));
  Pose const poseA = RandomPose(1.1, 23), poseB = RandomPose(2.9, 24);
  REQUIRE(pair.a->SetPose(poseA.position, poseA.rotation, error));
  REQUIRE(pair.b->SetPose(poseB.position, poseB.rotation, error));

  VectorX const g = Deviation(*c);
  VectorX const deltaG = g - gStart;
  CAPTURE(g.transpose(), deltaG.transpose(), g.norm());
  REQUIRE(g.norm() > 0.1);
  REQUIRE(deltaG.norm() > 0.1);
  if (saturation > 0) REQUIRE((saturation == 5.0 ? g.norm() < saturation : g.norm() > saturation));

  // Φᶜ at q is the reference formula on independently evaluated g and g⁰
  real const energy = ConstraintTestAccess::Energy(*c, h, ws);
  real const elastic = saturation > 0 ? compliance.stiffness * saturation * Ramp(g.norm(), saturation)
                                      : 0.5 * compliance.stiffness * g.squaredNorm();
  real const expectedEnergy = elastic + compliance.damping / (2 * h) * deltaG.squaredNorm();
  CAPTURE(energy, expectedEnergy);
  REQUIRE(Near(energy, expectedEnergy, 1e-13));

  internal::HessianAssembler assembler = MakeAssembler(*pair.scene, *c);
  VectorX const residual = Residual(*c, assembler, ws);
  MatrixX const fd = CentralDifferenceOverDofs(
      *c, kFdStep, [&] { return ConstraintTestAccess::Energy(*c, h, ws); });
  VectorX const fdResidual = fd.row(0).transpose();
  CAPTURE(residual.transpose(), fdResidual.transpose());
  REQUIRE(residual.norm() > 1);
  real const mismatch = MaxScaledError(residual, fdResidual);
  CAPTURE(mismatch);
  REQUIRE(mismatch <= kResidualTol);

  // the damping term is a large part of what was checked: without it the
  // residual differs from the one above by far more than the tolerance
  REQUIRE(c->SetDamping(0, error));
  VectorX const elasticOnly = Residual(*c, assembler, ws);
  REQUIRE(MaxScaledError(residual, elasticOnly) > 1e3 * kResidualTol);
}

// ---------------------------------------------------------------------------
// (b) saturation
// ---------------------------------------------------------------------------

TEST_CASE("saturated elastic term: kappa(0) = 2k, dU/dx = k gbar rho'(x), force capped at k gbar",
          "[constraints][compliant][saturation]") {
  real const k = 250, s = 0.04;  // k, ḡ
  CompliantParams const p{.stiffness = k, .damping = 0, .saturation = s};
  REQUIRE(p.IsSaturated());

  SECTION("at g = 0 exactly") {
    real const kappa = internal::CompliantKappa(p, 0);
    REQUIRE(kappa == 2 * k);  // the limit of k ḡ ρ'(x)/x as x → 0, exactly
    REQUIRE(internal::CompliantElasticEnergy(p, 0) == 0);
    // the vector forms: no NaN, zero force, Gauss–Newton scale 2k + d/h
    CompliantParams const damped{.stiffness = k, .damping = 3, .saturation = s};
    VectorX const zero = VectorX::Zero(3);
    VectorX f = VectorX::Constant(3, std::numeric_limits<real>::quiet_NaN());
    real const scale =
        internal::CompliantForceCoefficients(damped, zero, zero, kStageDuration, f);
    CAPTURE(f.transpose(), scale);
    REQUIRE(f.allFinite());
    REQUIRE(f.isZero(0));
    REQUIRE(scale == 2 * k + 3 / kStageDuration);
    REQUIRE(internal::CompliantEnergy(damped, zero, zero, kStageDuration) == 0);
  }

  SECTION("dU/dx matches kappa x = k gbar rho'(x), and kappa x <= k gbar") {
    // ‖g‖ ≪ ḡ, just below and just above ḡ, at ḡ, ≫ ḡ
    real const x = GENERATE_COPY(1e-9 * s, 1e-3 * s, 0.5 * s, s * (1 - 1e-7), s, s * (1 + 1e-7),
                                 2 * s, 1e4 * s);
    CAPTURE(x, x / s);
    real const kappa = internal::CompliantKappa(p, x);
    real const force = kappa * x;  // κ‖g‖, the elastic force magnitude
    REQUIRE(std::isfinite(kappa));
    REQUIRE(force > 0);
    // U = k ḡ ρ(x)
    real const energy = internal::CompliantElasticEnergy(p, x);
    CAPTURE(energy);
    REQUIRE(std::abs(energy - k * s * Ramp(x, s)) <= 8 * kEps * energy);
    // κ‖g‖ = k ḡ ρ'(x), ρ' written independently above
    real const expectedForce = k * s * RampDerivative(x, s);
    CAPTURE(force, expectedForce);
    REQUIRE(std::abs(force - expectedForce) <= 4 * kEps * k * s);
    // the cap k ḡ, up to the rounding of the two or three flops of κ x
    REQUIRE(force <= k * s * (1 + 4 * kEps));
    // dU/dx by central differences, step ε = 1e-6 x (within one branch
    // except at x = ḡ itself, where U'' is continuous, 0 on both sides, so
    // the difference quotient still converges at O(ε²))
    real const step = 1e-6 * x;
    real const dU = (internal::CompliantElasticEnergy(p, x + step) -
                     internal::CompliantElasticEnergy(p, x - step)) /
                    (2 * step);
    CAPTURE(dU);
    REQUIRE(std::abs(dU - force) <= 1e-7 * force);
  }

  SECTION("U is C1 across x = gbar") {
    // value and slope from below and from above meet at x = ḡ:
    // U(ḡ) = 2kḡ²/3, U'(ḡ) = kḡ
    for (real delta : {1e-6, 1e-9, 1e-12}) {
      CAPTURE(delta);
      real const below = s * (1 - delta), above = s * (1 + delta);
      real const uBelow = internal::CompliantElasticEnergy(p, below);
      real const uAbove = internal::CompliantElasticEnergy(p, above);
      real const slopeBelow = internal::CompliantKappa(p, below) * below;
      real const slopeAbove = internal::CompliantKappa(p, above) * above;
      // |U(ḡ ± δḡ) − U(ḡ)| <= U'(ḡ) δḡ (+ round-off)
      REQUIRE(std::abs(uBelow - 2 * k * s * s / 3) <= k * s * s * (delta + 4 * kEps));
      REQUIRE(std::abs(uAbove - 2 * k * s * s / 3) <= k * s * s * (delta + 4 * kEps));
      // U'(ḡ⁻) = kḡ(1 − δ²), U'(ḡ⁺) = kḡ exactly: they meet as δ → 0
      REQUIRE(std::abs(slopeBelow - slopeAbove) <= k * s * (delta * delta + 4 * kEps));
    }
    REQUIRE(internal::CompliantElasticEnergy(p, s) == 2 * k * s * s / 3);
  }

  SECTION("vector form: f = kappa g, no NaN, at g = 0 and around gbar") {
    Real3 const direction = Real3(1, -2, 2) / 3;
    for (real x : {0.0, 1e-300, 1e-3 * s, s, 10 * s, 1e6 * s}) {
      CAPTURE(x);
      VectorX const g = x * direction;
      VectorX f(3);
      real const scale = internal::CompliantForceCoefficients(p, g, g, kStageDuration, f);
      REQUIRE(f.allFinite());
      REQUIRE(std::isfinite(scale));
      REQUIRE(f.norm() <= k * s * (1 + 4 * kEps));
      real const kappa = internal::CompliantKappa(p, g.norm());
      REQUIRE(MaxScaledError(f, kappa * g) <= 4 * kEps);
      // with g⁰ = g the damping term vanishes; the scale is κ + d/h = κ, up to
      // the rounding of ‖g‖ (Eigen may sum it in another order through a
      // Ref than on a vector: one ulp of ‖g‖ moves κ = k ḡ/‖g‖ by one ulp)
      REQUIRE(std::abs(scale - kappa) <= 4 * kEps * kappa);
    }
  }
}

// ---------------------------------------------------------------------------
// (c) the Gauss–Newton Hessian
// ---------------------------------------------------------------------------

TEST_CASE("Gauss-Newton Hessian (kappa + d/h) JtJ is symmetric PSD",
          "[constraints][compliant][hessian]") {
  Type const type = GENERATE(Type::SphericalJoint, Type::PivotPosition);
  real const saturation = GENERATE(-1.0, 0.05);
  CAPTURE(Name(type), saturation);
  CompliantParams const compliance{.stiffness = 150, .damping = 4, .saturation = saturation};
  RigidPair pair = MakeRigidPair(RandomPose(0.9, 31), RandomPose(3.0, 32));
  Constraint* c = MakeConstraint(type, pair, compliance);
  int const m = c->GetDimension(), n = c->GetNumDofs();
  internal::TermWorkspace ws = SizedWorkspace(*c);
  ConstraintTestAccess::BeginStage(*c, ws);
  Error error;
  REQUIRE(pair.a->SetPose(Real3(0.2, 0.1, -0.3), Quat(Eigen::AngleAxis<real>(1.3, Real3::UnitY())),
                          error));

  internal::HessianAssembler assembler = MakeAssembler(*pair.scene, *c);
  MatrixX hessian;
  Residual(*c, assembler, ws, &hessian);
  // the local block the constraint built and the assembled one agree
  MatrixX const local = ws.hessian.topLeftCorner(n, n);
  REQUIRE(MaxScaledError(local, hessian) <= 1e-15);

  ConstraintTestAccess::EvaluateCurrent(*c, ws);
  MatrixX const jacobian = ws.jacobian.topLeftCorner(m, n);
  VectorX const g = ws.g.head(m);
  real const kappa = internal::CompliantKappa(compliance, g.norm());
  MatrixX const expected = (kappa + compliance.damping / kStageDuration) * jacobian.transpose() * jacobian;
  CAPTURE(g.norm(), kappa);
  REQUIRE(MaxScaledError(hessian, expected) <= 1e-13);

  real const largest = hessian.cwiseAbs().maxCoeff();
  REQUIRE(largest > 0);
  REQUIRE(MaxScaledError(local, local.transpose()) <= 1e-15);
  VectorX const eigenvalues = SymmetricEigenvalues(hessian);
  CAPTURE(eigenvalues.transpose());
  REQUIRE(eigenvalues.minCoeff() >= -1e-12 * eigenvalues.maxCoeff());
  // rank m: m positive eigenvalues (J has full row rank)
  REQUIRE(eigenvalues[n - m] > 1e-6 * eigenvalues.maxCoeff());
}

TEST_CASE("Gauss-Newton Hessian equals the finite-difference Jacobian of the residual at g = 0",
          "[constraints][compliant][hessian][derivatives]") {
  Type const type = GENERATE(Type::SphericalJoint, Type::PivotPosition);
  // with saturation κ(0) = 2k for any ḡ: the check also pins the limit. ḡ
  // is large because the saturated residual is only C¹ at g = 0: its
  // central difference errs by ~k ε/ḡ (the −k‖g‖g/ḡ term)
  real const saturation = GENERATE(-1.0, 1e3);
  CAPTURE(Name(type), saturation);
  CompliantParams const compliance{.stiffness = 150, .damping = 4, .saturation = saturation};
  Pose const poseA = RandomPose(0.8, 41), poseB = RandomPose(2.6, 42);
  RigidPair pair = MakeRigidPair(poseA, poseB);
  Constraint* c = MakeConstraint(type, pair, compliance);
  int const m = c->GetDimension(), n = c->GetNumDofs();
  internal::TermWorkspace ws = SizedWorkspace(*c);
  internal::HessianAssembler assembler = MakeAssembler(*pair.scene, *c);
  Error error;

  // satisfy the constraint (exactly for the pivot, to round-off for the
  // joint), then start the stage there so that g⁰ = 0 as well
  if (type == Type::PivotPosition) {
    REQUIRE(c->SetTargetPosition(pair.a->TransformPoint(kPivotA), error));
    REQUIRE(c->UpdateOldTarget(error));
  } else {
    Real3 const joint = pair.a->TransformPoint(kPivotA);
    REQUIRE(pair.b->SetPose(joint - poseB.rotation * kPivotB, poseB.rotation, error));
  }
  ConstraintTestAccess::BeginStage(*c, ws);
  VectorX const g = Deviation(*c);
  CAPTURE(g.transpose());
  REQUIRE(g.norm() <= 1e-15);
  REQUIRE(ConstraintTestAccess::StageStartValue(*c).norm() <= 1e-15);

  MatrixX hessian;
  VectorX const residual = Residual(*c, assembler, ws, &hessian);
  REQUIRE(residual.norm() <= 1e-12);

  // step 1e-6: round-off ~ulp(1)·(κ + d/h)/ε ~ 1e-7 absolute on entries up
  // to ~700; truncation O(ε²) unsaturated, k ε/ḡ ~ 1.5e-7 saturated
  real const step = 1e-6;
  MatrixX const fd = CentralDifferenceOverDofs(*c, step, [&] { return Residual(*c, assembler, ws); });
  CAPTURE(hessian, fd);
  REQUIRE(hessian.cwiseAbs().maxCoeff() > 100);
  real const mismatch = MaxScaledError(hessian, fd);
  CAPTURE(mismatch);
  REQUIRE(mismatch <= kResidualTol);

  // the scale is κ(0) + d/h with κ(0) = k unsaturated, 2k saturated: a
  // Hessian with k in place of 2k would miss by far more than the tolerance
  ConstraintTestAccess::EvaluateCurrent(*c, ws);
  MatrixX const jacobian = ws.jacobian.topLeftCorner(m, n);
  real const kappa0 = saturation > 0 ? 2 * compliance.stiffness : compliance.stiffness;
  MatrixX const expected =
      (kappa0 + compliance.damping / kStageDuration) * jacobian.transpose() * jacobian;
  REQUIRE(MaxScaledError(hessian, expected) <= 1e-13);
}

TEST_CASE("away from g = 0 the Gauss-Newton Hessian drops a visible second-derivative term",
          "[constraints][compliant][hessian]") {
  // The check at g = 0 is discriminating: where g ≠ 0 the same comparison
  // fails by far more than its tolerance (the dropped f·∇²g term).
  CompliantParams const compliance{.stiffness = 150, .damping = 4, .saturation = -1};
  RigidPair pair = MakeRigidPair(RandomPose(0.8, 41), RandomPose(2.6, 42));
  Constraint* c = MakeSphericalJoint(pair, compliance);
  internal::TermWorkspace ws = SizedWorkspace(*c);
  ConstraintTestAccess::BeginStage(*c, ws);
  REQUIRE(Deviation(*c).norm() > 0.1);
  internal::HessianAssembler assembler = MakeAssembler(*pair.scene, *c);
  MatrixX hessian;
  Residual(*c, assembler, ws, &hessian);
  MatrixX const fd = CentralDifferenceOverDofs(*c, 1e-6, [&] { return Residual(*c, assembler, ws); });
  REQUIRE(MaxScaledError(hessian, fd) > 1e3 * kResidualTol);
}

// ---------------------------------------------------------------------------
// (d) the range rule
// ---------------------------------------------------------------------------

TEST_CASE("IsRangeInactive: only when g and the stage-start g are both all zero",
          "[constraints][compliant][range]") {
  VectorX const zero = VectorX::Zero(3);
  VectorX oneComponent = VectorX::Zero(3);
  oneComponent[1] = -1e-300;  // the smallest violation still counts
  VectorX const full = VectorX::Constant(3, 0.2);
  VectorX const negativeZero = VectorX::Constant(3, -0.0);

  REQUIRE(internal::IsRangeInactive(zero, zero));
  REQUIRE(internal::IsRangeInactive(negativeZero, zero));
  // only one of them zero: active (the damping term still differences)
  REQUIRE_FALSE(internal::IsRangeInactive(zero, oneComponent));
  REQUIRE_FALSE(internal::IsRangeInactive(oneComponent, zero));
  REQUIRE_FALSE(internal::IsRangeInactive(zero, full));
  REQUIRE_FALSE(internal::IsRangeInactive(full, zero));
  REQUIRE_FALSE(internal::IsRangeInactive(full, full));
  REQUIRE_FALSE(internal::IsRangeInactive(oneComponent, oneComponent));

  // an active range term with g = 0 but g⁰ ≠ 0 has energy and force
  CompliantParams const p{.stiffness = 10, .damping = 2, .saturation = -1};
  REQUIRE(internal::CompliantEnergy(p, zero, full, kStageDuration) > 0);
  VectorX f(3);
  internal::CompliantForceCoefficients(p, zero, full, kStageDuration, f);
  REQUIRE(f.norm() > 0);
}

// ---------------------------------------------------------------------------
// (e) the constraint Hessian choices
// ---------------------------------------------------------------------------

TEST_CASE("constraint Hessian: Gauss-Newton, geometric stiffness exact and in its diagonal form",
          "[constraints][compliant][geometric-stiffness]") {
  Type const type = GENERATE(Type::SphericalJoint, Type::PivotPosition);
  CAPTURE(Name(type));
  CompliantParams const compliance{.stiffness = 150, .damping = 4, .saturation = -1};
  RigidPair pair = MakeRigidPair(RandomPose(0.6, 31), RandomPose(2.4, 32));
  Constraint* c = MakeConstraint(type, pair, compliance);
  int const m = c->GetDimension(), n = c->GetNumDofs();
  internal::TermWorkspace ws = SizedWorkspace(*c);
  ConstraintTestAccess::BeginStage(*c, ws);
  Error error;
  Pose const poseA = RandomPose(1.1, 33), poseB = RandomPose(2.9, 34);
  REQUIRE(pair.a->SetPose(poseA.position, poseA.rotation, error));
  REQUIRE(pair.b->SetPose(poseB.position, poseB.rotation, error));
  internal::HessianAssembler assembler = MakeAssembler(*pair.scene, *c);

  // the reference blocks from g, J and G, formed here
  VectorX const g = Deviation(*c);
  VectorX const f = compliance.stiffness * g +
                    compliance.damping / kStageDuration * (g - ConstraintTestAccess::StageStartValue(*c));
  real const scale = compliance.stiffness + compliance.damping / kStageDuration;
  ConstraintTestAccess::EvaluateCurrent(*c, ws);
  MatrixX const jacobian = ws.jacobian.topLeftCorner(m, n);
  MatrixX const gaussNewton = scale * jacobian.transpose() * jacobian;
  MatrixX const curvature = ConstraintTestAccess::Curvature(*c, f);
  REQUIRE(curvature.norm() > 1);
  MatrixX const exact = gaussNewton + curvature;
  REQUIRE(SymmetricEigenvalues(exact).minCoeff() < -1);  // indefinite here: projection has work
  MatrixX diagonal = gaussNewton;
  for (int j = 0; j < n; ++j) diagonal(j, j) += curvature.col(j).norm();

  MatrixX hessian;
  VectorX const residual = Residual(*c, assembler, ws, &hessian, ConstraintHessian::GaussNewton);
  REQUIRE(MaxScaledError(hessian, gaussNewton) <= 1e-12);
  auto check = [&](ConstraintHessian mode, bool project, MatrixX const& expected) {
    CAPTURE(ToString(mode), project);
    MatrixX block;
    VectorX const r = Residual(*c, assembler, ws, &block, mode, project);
    REQUIRE(r == residual);  // the gradient does not depend on the Hessian
    CAPTURE(block, expected);
    REQUIRE(MaxScaledError(block, expected) <= 1e-10);
  };
  check(ConstraintHessian::GeometricStiffness, false, exact);
  // projected iterations: the diagonal form, PSD
  check(ConstraintHessian::GeometricStiffness, true, diagonal);
  REQUIRE(SymmetricEigenvalues(diagonal).minCoeff() >= -1e-12 * diagonal.norm());
  check(ConstraintHessian::GeometricStiffnessDiagonal, false, diagonal);
  check(ConstraintHessian::GeometricStiffnessDiagonal, true, diagonal);
  // a constraint's own choice overrides the scene's
  REQUIRE(c->SetHessianApproximation(ConstraintHessian::GaussNewton, error));
  check(ConstraintHessian::GeometricStiffness, false, gaussNewton);
  REQUIRE(c->SetHessianApproximation(ConstraintHessian::SceneDefault, error));
  check(ConstraintHessian::GeometricStiffness, false, exact);
  REQUIRE_FALSE(c->SetHessianApproximation(static_cast<ConstraintHessian>(9), error));
  REQUIRE(error.GetCode() == ErrorCode::InvalidArgument);
  REQUIRE(error.GetMessage().find("hessianApproximation") != std::string::npos);
  REQUIRE(c->GetHessianApproximation() == ConstraintHessian::SceneDefault);
}

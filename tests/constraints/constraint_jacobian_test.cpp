// Constraint Jacobians against central differences of g in the tangent
// increments of docs/design.md §3, for every constraint type, at rotations near 0,
// moderate, and within 1e-3 of π, with non-zero pivots and non-trivial frames
// and targets. g itself is checked against the reference formula
// (constraints.md) evaluated here with Eigen (matrices, Eigen::AngleAxis for
// Log), so a wrong g with a consistent J cannot pass either.
//
// Range rows (JointRotationRange, RigidPrismaticJoint's third row) are checked
// on both sides of each bound and inside: every component is put in each of
// the three regions, a margin (1e-3) ≫ the difference step away from the
// nearest bound; inside, g_j and row j of J must be exactly zero.
#include <numbers>

#include "constraint_test_util.h"

using namespace superdex;
using namespace superdex::test;

namespace {

constexpr real kPi = std::numbers::pi_v<real>;

// g is O(1) and linear in t, smooth in δθ with O(1) derivatives: step 1e-6
// gives a truncation error ~ε²/6 ~ 2e-13 and a round-off error ~ulp(1)/ε ~
// 2e-10. The Jacobian must match to 1e-6 (relative, entrywise, in units of
// max(|a|, |b|, 1)); the measured error is <= 7.3e-10 over all types.
constexpr real kFdStep = 1e-6;
constexpr real kJacobianTol = 1e-6;
// g against the formula: the same few flops on O(1) numbers, in a different
// order (quaternions in the library, matrices here); Log is well conditioned
// because every rotation-vector g below stays away from |g| = π. Measured:
// <= 5.6e-16.
constexpr real kValueTol = 1e-14;
// distance of a bounded measure from its nearest bound: ≫ the step (a step
// moves the measure by ~1e-6), so no difference crosses a bound
constexpr real kRangeMargin = 1e-3;
// a Jacobian row or column that must be non-zero has at least this norm
// (translation columns: unit; rotation columns of a rotational g: ≥ 1, since
// J_l⁻¹ has singular values ≥ 1; −Hat(R r) e_j: ~|r| with the generic pivots)
constexpr real kNonZeroNorm = 0.05;

struct PoseCase {
  char const* name;
  real angleA, angleB;
};
constexpr PoseCase kPoseCases[] = {
    {"identity / identity", 0, 0},
    {"near zero", 1e-9, 3e-7},
    {"moderate", 0.7, 2.1},
    {"within 1e-3 of pi", kPi - 1e-3, kPi - 2e-4},
    {"mixed: near pi / near zero", kPi - 5e-4, 1e-6},
};
constexpr int kNumPoseCases = static_cast<int>(std::size(kPoseCases));

// Non-trivial frames and targets: generic, non-axis-aligned.
// joint frame R₀, world, at creation (A-local R₀ = R_Aᵀ kJointFrame)
Quat const kJointFrame = QuatOfRotationVector(Real3(0.3, -0.5, 0.8));
// a moderate rotation (|ψ| ≈ 0.71 rad) composed into rotation targets
Real3 const kModerateRotation(0.4, -0.3, 0.5);
// pivot frame R_ℓ of RigidPivotRotation, body coordinates
Quat const kLocalRotation = QuatOfRotationVector(Real3(-0.6, 0.2, 0.35));
// target rotation of RigidPivotToRigidTarget, world (with kTargetPosition)
Quat const kTargetRotation = QuatOfRotationVector(Real3(1.1, 0.4, -0.7));
// s_ref of RigidPrismaticJoint when !offsetAroundRest, joint frame [m]
Real3 const kReferenceOffset(0.1, -0.2, 0.3);

internal::CompliantParams const kCompliance{.stiffness = 1e3, .damping = 0, .saturation = -1};

/// A row of J that must be non-zero (matched against differences), or exactly
/// zero (a range component inside its bounds).
enum class Row { Active, Zero };

/// g against `expectedG`, J against central differences of GetDeviation,
/// and the curvature G against central differences of Jᵀw (CheckCurvature).
/// Active rows: non-zero in J and in the differences, and matching. Zero
/// rows: g_i, row i of J and row i of the differences exactly 0 (no
/// tolerance). When every row is active, every column must be non-zero too,
/// so no column can match by being zero on both sides.
void CheckJacobian(Constraint const& c, VectorX const& expectedG,
                   std::array<Row, 3> const& rows = {Row::Active, Row::Active, Row::Active}) {
  int const m = c.GetDimension(), n = c.GetNumDofs();
  REQUIRE(m == 3);
  internal::TermWorkspace ws;
  ws.Reserve(m, n);
  ConstraintTestAccess::EvaluateCurrent(c, ws);
  VectorX const g = ws.g.head(m);
  MatrixX const jacobian = ws.jacobian.topLeftCorner(m, n);

  // the private Evaluate and the public GetDeviation agree, and both match
  // the reference formula
  CAPTURE(g.transpose(), expectedG.transpose());
  REQUIRE(g == Deviation(c));
  real const valueError = MaxScaledError(g, expectedG);
  CAPTURE(valueError);
  REQUIRE(valueError <= kValueTol);

  MatrixX const fd = CentralDifferenceOverDofs(c, kFdStep, [&] { return Deviation(c); });
  CAPTURE(jacobian, fd);
  bool allActive = true;
  for (int i = 0; i < m; ++i) {
    CAPTURE(i);
    if (rows[i] == Row::Zero) {
      allActive = false;
      REQUIRE(g[i] == 0);
      REQUIRE((jacobian.row(i).array() == 0).all());
      REQUIRE((fd.row(i).array() == 0).all());
    } else {
      REQUIRE(jacobian.row(i).norm() > kNonZeroNorm);
      REQUIRE(fd.row(i).norm() > kNonZeroNorm);
    }
  }
  if (allActive) {
    for (int j = 0; j < n; ++j) {
      CAPTURE(j);
      REQUIRE(jacobian.col(j).norm() > kNonZeroNorm);
      REQUIRE(fd.col(j).norm() > kNonZeroNorm);
    }
  }
  real const error = MaxScaledError(jacobian, fd);
  CAPTURE(error);
  REQUIRE(error <= kJacobianTol);
  bool const anyActive = std::find(rows.begin(), rows.end(), Row::Active) != rows.end();
  CheckCurvature(c, anyActive);
}

Real33 Matrix(Quat const& q) {
  return q.toRotationMatrix();
}

/// A-local joint frame R₀ = R_Aᵀ R₀,world (the conversion made at creation).
Real33 LocalJointFrame(Pose const& poseA) {
  return Matrix(poseA.rotation).transpose() * Matrix(kJointFrame);
}

}  // namespace

// ---------------------------------------------------------------------------
// Bilateral types

TEST_CASE("constraint Jacobians match central differences of g", "[constraints][derivatives]") {
  int const caseIndex = GENERATE(range(0, kNumPoseCases));
  unsigned const seed = GENERATE(1u, 2u);
  PoseCase const& poseCase = kPoseCases[caseIndex];
  CAPTURE(poseCase.name, poseCase.angleA, poseCase.angleB, seed);
  Pose const poseA = RandomPose(poseCase.angleA, 10 * seed);
  Pose const poseB = RandomPose(poseCase.angleB, 10 * seed + 1);
  RigidPair pair = MakeRigidPair(poseA, poseB);
  Real33 const rotationA = Matrix(poseA.rotation), rotationB = Matrix(poseB.rotation);
  Error error;

  SECTION("RigidSphericalJoint: g = T_A(r_A) - T_B(r_B)") {
    Constraint* c = MakeSphericalJoint(pair, kCompliance);
    REQUIRE(c->GetType() == ConstraintType::RigidSphericalJoint);
    REQUIRE(c->GetNumDofs() == 12);
    VectorX const expected =
        (poseA.position + rotationA * kPivotA) - (poseB.position + rotationB * kPivotB);
    CheckJacobian(*c, expected);
  }
  SECTION("RigidPivotPosition: g = T(r) - p") {
    Constraint* c = MakePivotPosition(pair, kCompliance);
    REQUIRE(c->GetType() == ConstraintType::RigidPivotPosition);
    REQUIRE(c->GetNumDofs() == 6);
    VectorX const expected = poseA.position + rotationA * kPivotA - kTargetPosition;
    CheckJacobian(*c, expected);
  }
  SECTION("RigidPivotToRigidTarget: g = T(r) - T^(r)") {
    RigidPivotToRigidTargetConstraintParams p;
    p.actor = pair.a->GetHandle();
    p.localPos = kPivotA;
    p.position = kTargetPosition;
    p.rotation = kTargetRotation;
    p.stiffness = kCompliance.stiffness;
    Constraint* c = pair.scene->CreateRigidPivotToRigidTargetConstraint(p, error);
    INFO(error.ToString());
    REQUIRE(c);
    REQUIRE(c->GetType() == ConstraintType::RigidPivotToRigidTarget);
    REQUIRE(c->GetNumDofs() == 6);
    // the target point moves with the target's rotation: t^ + R^ r, not t^
    VectorX const expected = (poseA.position + rotationA * kPivotA) -
                             (kTargetPosition + Matrix(kTargetRotation) * kPivotA);
    CheckJacobian(*c, expected);
  }
  SECTION("RigidPivotRotation: g = Log(R R_l R^^-1)") {
    // The target is the body's pivot frame times a moderate rotation,
    // R^ = R R_ℓ Exp(ψ), so g = Log(R R_ℓ Exp(−ψ) (R R_ℓ)ᵀ) = −R R_ℓ ψ has
    // |g| = |ψ| ≈ 0.71 even when the body rotation is within 1e-3 of π: a
    // rotation-vector g near |g| = π would flip sign across Log's cut and no
    // difference quotient could straddle it.
    Quat const target =
        (poseA.rotation * kLocalRotation * QuatOfRotationVector(kModerateRotation)).normalized();
    RigidPivotRotationConstraintParams p;
    p.actor = pair.a->GetHandle();
    p.localRotation = kLocalRotation;
    p.rotation = target;
    p.stiffness = kCompliance.stiffness;
    Constraint* c = pair.scene->CreateRigidPivotRotationConstraint(p, error);
    INFO(error.ToString());
    REQUIRE(c);
    REQUIRE(c->GetType() == ConstraintType::RigidPivotRotation);
    REQUIRE(c->GetNumDofs() == 3);
    VectorX const expected =
        ReferenceLog(rotationA * Matrix(kLocalRotation) * Matrix(target).transpose());
    REQUIRE(std::abs(expected.norm() - kModerateRotation.norm()) < 1e-12);
    CheckJacobian(*c, expected);
  }
  SECTION("JointRotationTracking: g = Log((R_A R^ R0)^-1 R_B R0)") {
    JointRotationTrackingConstraintParams p;
    p.actorA = pair.a->GetHandle();
    p.actorB = pair.b->GetHandle();
    p.jointFrame = kJointFrame;
    p.stiffness = kCompliance.stiffness;
    Constraint* c = pair.scene->CreateJointRotationTrackingConstraint(p, error);
    INFO(error.ToString());
    REQUIRE(c);
    REQUIRE(c->GetType() == ConstraintType::JointRotationTracking);
    REQUIRE(c->GetNumDofs() == 6);
    // the target starts at the creation-time relative rotation: g = 0
    CAPTURE(Deviation(*c).transpose());
    REQUIRE(Deviation(*c).norm() <= kValueTol);

    // Target = creation-time relative rotation R_Aᵀ R_B times a moderate
    // rotation: g = Log(R₀ᵀ Exp(−ψ) R₀) ≠ 0 with |g| = |ψ| ≈ 0.71, away from
    // Log's cut at |g| = π even when both bodies are near π.
    Quat const target =
        (poseA.rotation.conjugate() * poseB.rotation * QuatOfRotationVector(kModerateRotation))
            .normalized();
    REQUIRE(c->SetTargetRotation(target, error));
    Real33 const frame = LocalJointFrame(poseA);
    VectorX const expected =
        ReferenceLog((rotationA * Matrix(target) * frame).transpose() * rotationB * frame);
    REQUIRE(std::abs(expected.norm() - kModerateRotation.norm()) < 1e-12);
    CheckJacobian(*c, expected);
  }
}

// ---------------------------------------------------------------------------
// Range types: every component on each side of its bounds and inside

TEST_CASE("JointRotationRange: g and J on both sides of each bound and inside",
          "[constraints][derivatives][range]") {
  int const caseIndex = GENERATE(range(0, kNumPoseCases));
  unsigned const seed = GENERATE(1u, 2u);
  bool const rangeAroundRest = GENERATE(false, true);
  bool const oneSided = GENERATE(false, true);
  // regions of the three components, base 3: all 27 combinations, so each
  // component is in each region with the others in every region
  int const regionCode = GENERATE(range(0, 27));
  std::array<RangeRegion, 3> regions;
  for (int j = 0, code = regionCode; j < 3; ++j, code /= 3)
    regions[j] = static_cast<RangeRegion>(code % 3);

  PoseCase const& poseCase = kPoseCases[caseIndex];
  CAPTURE(poseCase.name, seed, rangeAroundRest, oneSided, ToString(regions[0]),
          ToString(regions[1]), ToString(regions[2]));
  Pose const poseA = RandomPose(poseCase.angleA, 10 * seed);
  Pose const poseB = RandomPose(poseCase.angleB, 10 * seed + 1);
  RigidPair pair = MakeRigidPair(poseA, poseB);
  Real33 const rotationA = Matrix(poseA.rotation), rotationB = Matrix(poseB.rotation);
  Real33 const frame = LocalJointFrame(poseA);
  // R₀ᵀ R_Aᵀ R_B R₀, the relative rotation in the joint frame
  Real33 const relative = frame.transpose() * rotationA.transpose() * rotationB * frame;

  JointRotationRangeConstraintParams p;
  p.actorA = pair.a->GetHandle();
  p.actorB = pair.b->GetHandle();
  p.jointFrame = kJointFrame;
  p.stiffness = kCompliance.stiffness;
  p.rangeAroundRest = rangeAroundRest;
  Real33 referenceRotation;
  if (rangeAroundRest) {
    // R_ref = the creation-time relative rotation: r_AB = 0
    referenceRotation = relative;
  } else {
    // R_ref = R_rel Exp(ψ)ᵀ: r_AB = Log(R_rel Exp(ψ) R_relᵀ) = R_rel ψ, a
    // moderate rotation vector (|r_AB| ≈ 0.71, far from the cut at π) that
    // depends on the pose, even when both bodies are near π
    Quat const relativeQuat =
        (kJointFrame.conjugate() * poseB.rotation * poseA.rotation.conjugate() * kJointFrame)
            .normalized();
    p.referenceRotation =
        (relativeQuat * QuatOfRotationVector(kModerateRotation).conjugate()).normalized();
    referenceRotation = Matrix(p.referenceRotation);
  }
  // r_AB = Log(R₀⁻¹ R_A⁻¹ R_B R₀ R_ref⁻¹)
  Real3 const expectedMeasure = ReferenceLog(relative * referenceRotation.transpose());

  // measure r_AB with an unbounded probe, then bound around the measured value
  Error error;
  Error probeError;
  Constraint* probe = pair.scene->CreateJointRotationRangeConstraint(p, probeError);
  INFO(probeError.ToString());
  REQUIRE(probe);
  Real3 const measure = dynamic_cast<JointRotationRangeConstraint&>(*probe).GetRelativeRotation();
  CAPTURE(measure.transpose(), expectedMeasure.transpose());
  REQUIRE(MaxScaledError(measure, expectedMeasure) <= kValueTol);
  REQUIRE(pair.scene->DestroyConstraint(probe, error));

  std::array<Bounds, 3> bounds;
  std::array<Row, 3> rows;
  Real3 expected;
  for (int j = 0; j < 3; ++j) {
    bounds[j] = BoundsPlacing(measure[j], regions[j], kRangeMargin, oneSided);
    p.lowerLimits[j] = bounds[j].lower;
    p.upperLimits[j] = bounds[j].upper;
    rows[j] = regions[j] == RangeRegion::Inside ? Row::Zero : Row::Active;
    // g_j = max(x − u, l − x, 0) >= 0: the margin on either side
    expected[j] = ReferenceViolation(expectedMeasure[j], bounds[j]);
    REQUIRE(expected[j] >= 0);
    if (regions[j] != RangeRegion::Inside) REQUIRE(Near(expected[j], kRangeMargin, 1e-9));
  }
  Constraint* c = pair.scene->CreateJointRotationRangeConstraint(p, error);
  INFO(error.ToString());
  REQUIRE(c);
  REQUIRE(c->GetType() == ConstraintType::JointRotationRange);
  REQUIRE(c->GetNumDofs() == 6);
  CheckJacobian(*c, expected, rows);
}

TEST_CASE("RigidPrismaticJoint: g and J, the travel row on both sides of each limit and inside",
          "[constraints][derivatives][range]") {
  int const caseIndex = GENERATE(range(0, kNumPoseCases));
  unsigned const seed = GENERATE(1u, 2u);
  bool const offsetAroundRest = GENERATE(false, true);
  bool const oneSided = GENERATE(false, true);
  RangeRegion const region =
      GENERATE(RangeRegion::BelowLower, RangeRegion::Inside, RangeRegion::AboveUpper);

  PoseCase const& poseCase = kPoseCases[caseIndex];
  CAPTURE(poseCase.name, seed, offsetAroundRest, oneSided, ToString(region));
  Pose const poseA = RandomPose(poseCase.angleA, 10 * seed);
  Pose const poseB = RandomPose(poseCase.angleB, 10 * seed + 1);
  RigidPair pair = MakeRigidPair(poseA, poseB);
  Real33 const rotationA = Matrix(poseA.rotation);
  Real33 const frame = LocalJointFrame(poseA);
  Real3 const separation = poseB.position - poseA.position;

  RigidPrismaticJointConstraintParams p;
  p.actorA = pair.a->GetHandle();
  p.actorB = pair.b->GetHandle();
  p.jointFrame = kJointFrame;
  p.offsetAroundRest = offsetAroundRest;
  p.referenceOffset = kReferenceOffset;
  p.stiffness = kCompliance.stiffness;
  // s = R₀⁻¹ R_A⁻¹ (t_B − t_A) − s_ref; around rest, s_ref is the creation
  // offset and s = 0
  Real3 const rawOffset = (rotationA * frame).transpose() * separation;
  Real3 const expectedOffset = rawOffset - (offsetAroundRest ? rawOffset : kReferenceOffset);

  // measure s with an unlimited probe, then limit around the measured s₃
  Error error;
  Error probeError;
  Constraint* probe = pair.scene->CreateRigidPrismaticJointConstraint(p, probeError);
  INFO(probeError.ToString());
  REQUIRE(probe);
  Real3 const offset = dynamic_cast<RigidPrismaticJointConstraint&>(*probe).GetOffset();
  CAPTURE(offset.transpose(), expectedOffset.transpose());
  REQUIRE(MaxScaledError(offset, expectedOffset) <= kValueTol);
  REQUIRE(pair.scene->DestroyConstraint(probe, error));

  Bounds const limits = BoundsPlacing(offset.z(), region, kRangeMargin, oneSided);
  p.lowerLimit = limits.lower;
  p.upperLimit = limits.upper;
  // g₁ = s₁, g₂ = s₂; g₃ = s₃ − u above u, s₃ − l below l (signed), 0 inside
  real const s3 = expectedOffset.z();
  real expectedTravel = 0;
  if (region == RangeRegion::AboveUpper) {
    expectedTravel = s3 - limits.upper;
    REQUIRE(Near(expectedTravel, kRangeMargin, 1e-9));
  } else if (region == RangeRegion::BelowLower) {
    expectedTravel = s3 - limits.lower;
    REQUIRE(Near(expectedTravel, -kRangeMargin, 1e-9));
  }
  Real3 const expected(expectedOffset.x(), expectedOffset.y(), expectedTravel);

  Constraint* c = pair.scene->CreateRigidPrismaticJointConstraint(p, error);
  INFO(error.ToString());
  REQUIRE(c);
  REQUIRE(c->GetType() == ConstraintType::RigidPrismaticJoint);
  REQUIRE(c->GetNumDofs() == 9);
  CheckJacobian(
      *c, expected,
      {Row::Active, Row::Active, region == RangeRegion::Inside ? Row::Zero : Row::Active});
}

// Constraint Jacobians against central differences of g in the tangent
// increments of design.md §3, for every constraint type, at rotations near 0,
// moderate, and within 1e-3 of π, with non-zero pivots. g itself is checked
// against the reference formula (constraints.md) evaluated here with Eigen, so
// a wrong g with a consistent J cannot pass either.
#include "constraint_test_util.h"

#include <numbers>

using namespace superdex;
using namespace superdex::test;

namespace {

constexpr real kPi = std::numbers::pi_v<real>;

// g is O(1) and linear in t, smooth in δθ with O(1) derivatives: step 1e-6
// gives a truncation error ~ε²/6 ~ 2e-13 and a round-off error ~ulp(1)/ε ~
// 2e-10. The Jacobian must match to 1e-6 (relative, entrywise, in units of
// max(|a|, |b|, 1)); the measured error is ~1e-10.
constexpr real kFdStep = 1e-6;
constexpr real kJacobianTol = 1e-6;
// g against the formula: both sides are the same few flops on O(1) numbers.
constexpr real kValueTol = 1e-14;

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

void CheckJacobian(Constraint const& c, VectorX const& expectedG) {
  int const m = c.GetDimension(), n = c.GetNumDofs();
  internal::ConstraintWorkspace ws;
  ws.Reserve(m, n);
  ConstraintTestAccess::EvaluateCurrent(c, ws);
  VectorX const g = ws.g.head(m);
  MatrixX const jacobian = ws.jacobian.topLeftCorner(m, n);

  // the private Evaluate and the public GetDeviation agree, and both match
  // the reference formula
  CAPTURE(g.transpose(), expectedG.transpose());
  REQUIRE(g == Deviation(c));
  REQUIRE(MaxScaledError(g, expectedG) <= kValueTol);

  MatrixX const fd = CentralDifferenceOverDofs(c, kFdStep, [&] { return Deviation(c); });
  CAPTURE(jacobian, fd);
  // every column is non-zero (translations: ±I; rotations: −Hat(R r) e_j
  // with a generic arm), so no column can match by being zero on both sides
  for (int j = 0; j < n; ++j) {
    CAPTURE(j);
    REQUIRE(jacobian.col(j).norm() > 0.05);
    REQUIRE(fd.col(j).norm() > 0.05);
  }
  real const error = MaxScaledError(jacobian, fd);
  CAPTURE(error);
  REQUIRE(error <= kJacobianTol);
}

}  // namespace

TEST_CASE("constraint Jacobians match central differences of g",
          "[constraints][derivatives]") {
  int const caseIndex = GENERATE(range(0, static_cast<int>(std::size(kPoseCases))));
  unsigned const seed = GENERATE(1u, 2u);
  PoseCase const& poseCase = kPoseCases[caseIndex];
  CAPTURE(poseCase.name, poseCase.angleA, poseCase.angleB, seed);
  Pose const poseA = RandomPose(poseCase.angleA, 10 * seed);
  Pose const poseB = RandomPose(poseCase.angleB, 10 * seed + 1);
  RigidPair pair = MakeRigidPair(poseA, poseB);
  internal::CompliantParams const compliance{.stiffness = 1e3, .damping = 0, .saturation = -1};

  SECTION("RigidSphericalJoint: g = T_A(r_A) - T_B(r_B)") {
    Constraint* c = MakeSphericalJoint(pair, compliance);
    REQUIRE(c->GetType() == ConstraintType::RigidSphericalJoint);
    REQUIRE(c->GetNumDofs() == 12);
    VectorX const expected = (poseA.position + poseA.rotation.toRotationMatrix() * kPivotA) -
                             (poseB.position + poseB.rotation.toRotationMatrix() * kPivotB);
    CheckJacobian(*c, expected);
  }
  SECTION("RigidPivotPosition: g = T(r) - p") {
    Constraint* c = MakePivotPosition(pair, compliance);
    REQUIRE(c->GetType() == ConstraintType::RigidPivotPosition);
    REQUIRE(c->GetNumDofs() == 6);
    VectorX const expected =
        poseA.position + poseA.rotation.toRotationMatrix() * kPivotA - kTargetPosition;
    CheckJacobian(*c, expected);
  }
}

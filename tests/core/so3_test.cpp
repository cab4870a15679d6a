// SO(3) maps (core/so3.h): Exp/Log round trips over the whole angle range,
// including the series branches near 0 and the neighbourhood of π, and every
// Jacobian against central differences of the relation that defines it.
//
// Tolerances are stated as |a − b| <= tol · max(|a|, |b|, 1) entrywise
// (style habit 11) unless a comment says otherwise.
#include "test_support.h"
#include "white_box.h"

#include <cmath>
#include <numbers>
#include <random>

using namespace superdex;
using namespace superdex::test;

namespace {

constexpr real kPi = std::numbers::pi_v<real>;
constexpr real kEps = std::numeric_limits<real>::epsilon();

// Log(Exp(v)) = v, relative to |v|. Exp evaluates sin(θ/2)/θ and cos(θ/2)
// (or their series) with a few ulps of relative error; Log takes
// θ = 2 atan2(|v|, w), which is well conditioned everywhere in [0, π): near
// π, w = cos(θ/2) is small but carries an *absolute* error of ~1 ulp of 1,
// which moves θ by ~2 ulps of 1 — still ~1e-16 relative to θ ≈ π. Every path
// is therefore good to ~10 ulps (~2e-15); 1e-12 leaves three decades of
// margin for other libm implementations, and is still far tighter than any
// branch mistake (a wrong series coefficient shows at 1e-9 or worse).
constexpr real kRoundTripTol = 1e-12;

// Rotation matrices compared entrywise: entries are O(1) and built from
// quaternions with a few ulps of error each.
constexpr real kMatrixTol = 1e-13;

// Central differences with step 1e-5 of maps whose values are O(π): the
// truncation error is ε²/6 · |f'''| ~ 1e-11 (f''' is O(1) for |φ| <= π − 1e-3,
// J_l⁻¹ being analytic for |φ| < 2π), the round-off error ulp(π)/ε ~ 1e-10.
// 1e-8 leaves two decades of margin; a wrong coefficient in any Jacobian
// (or a left/right swap, see the last test) errs by 1e-3 or more.
constexpr real kFdStep = 1e-5;
constexpr real kJacobianTol = 1e-8;

// J J⁻¹ = I: products of O(1) matrices with a few ulps of error each.
constexpr real kInverseTol = 1e-13;

Real3 RandomUnit(std::mt19937& rng) {
  std::normal_distribution<real> normal;
  Real3 v;
  do {
    v = Real3(normal(rng), normal(rng), normal(rng));
  } while (v.norm() < 1e-3);
  return v.normalized();
}

Quat RandomQuat(std::mt19937& rng) {
  std::normal_distribution<real> normal;
  Eigen::Vector4d c;
  do {
    c = Eigen::Vector4d(normal(rng), normal(rng), normal(rng), normal(rng));
  } while (c.norm() < 1e-3);
  c.normalize();
  return Quat(c[0], c[1], c[2], c[3]);
}

// Log(Exp(v)) relative error |Log(Exp(v)) − v| / |v|, through the quaternion
// and the matrix paths; the reference rotation also comes from Eigen's
// AngleAxis, independent of superdex::Exp.
struct RoundTripErrors {
  real viaQuat, viaMatrix, viaAngleAxis;
};
RoundTripErrors LogExpErrors(Real3 const& v) {
  real const n = v.norm();
  Eigen::AngleAxis<real> const angleAxis(n, v / n);
  return {(Log(Exp(v)) - v).norm() / n, (Log(ExpMatrix(v)) - v).norm() / n,
          (Log(Quat(angleAxis)) - v).norm() / n};
}

real MaxAbs(MatrixX const& m) { return m.cwiseAbs().maxCoeff(); }

// Central-difference Jacobian of f: R³ → R³ at δ = 0.
template <class F>
Real33 CentralDifference(F const& f) {
  Real33 jacobian;
  for (int j = 0; j < 3; ++j) {
    Real3 delta = Real3::Zero();
    delta[j] = kFdStep;
    jacobian.col(j) = (f(delta) - f(-delta)) / (2 * kFdStep);
  }
  return jacobian;
}

// The relations that define each Jacobian (so3.h):
//   Log(Exp(δ) Exp(φ)) ≈ φ + J_l⁻¹(φ) δ        Log(Exp(φ) Exp(δ)) ≈ φ + J_r⁻¹(φ) δ
//   Exp(φ + δ) ≈ Exp(J_l(φ) δ) Exp(φ)          Exp(φ + δ) ≈ Exp(φ) Exp(J_r(φ) δ)
Real33 FdLeftJacobianInverse(Real3 const& phi) {
  return CentralDifference([&](Real3 const& d) -> Real3 { return Log(Exp(d) * Exp(phi)); });
}
Real33 FdRightJacobianInverse(Real3 const& phi) {
  return CentralDifference([&](Real3 const& d) -> Real3 { return Log(Exp(phi) * Exp(d)); });
}
Real33 FdLeftJacobian(Real3 const& phi) {
  Quat const inverse = Exp(phi).conjugate();
  return CentralDifference([&](Real3 const& d) -> Real3 { return Log(Exp(phi + d) * inverse); });
}
Real33 FdRightJacobian(Real3 const& phi) {
  Quat const inverse = Exp(phi).conjugate();
  return CentralDifference([&](Real3 const& d) -> Real3 { return Log(inverse * Exp(phi + d)); });
}

}  // namespace

TEST_CASE("Log inverts Exp from 1e-12 rad to within 1e-6 of pi", "[core][so3]") {
  // log-spaced magnitudes 1e-12 … 1 (half decades, so both sides of the
  // series switches at 1e-8 and 1e-4 are hit), then up to π − 1e-6
  DynamicArray<real> magnitudes;
  for (int k = -24; k <= 0; ++k) magnitudes.push_back(std::pow(10.0, 0.5 * k));
  for (real m : {2e-8, 1e-4 * (1 - 1e-9), 1e-4 * (1 + 1e-9), 2.0, 3.0, kPi - 1e-3, kPi - 1e-4,
                 kPi - 1e-5, kPi - 1e-6})
    magnitudes.push_back(m);

  std::mt19937 rng(20240611);
  real worstQuat = 0, worstMatrix = 0, worstAngleAxis = 0;
  for (real magnitude : magnitudes) {
    for (int direction = 0; direction < 8; ++direction) {
      Real3 const v = magnitude * RandomUnit(rng);
      CAPTURE(magnitude, v.transpose());
      RoundTripErrors const e = LogExpErrors(v);
      CAPTURE(e.viaQuat, e.viaMatrix, e.viaAngleAxis);
      REQUIRE(e.viaQuat <= kRoundTripTol);
      REQUIRE(e.viaMatrix <= kRoundTripTol);
      REQUIRE(e.viaAngleAxis <= kRoundTripTol);
      worstQuat = std::max(worstQuat, e.viaQuat);
      worstMatrix = std::max(worstMatrix, e.viaMatrix);
      worstAngleAxis = std::max(worstAngleAxis, e.viaAngleAxis);
    }
  }
  WARN("worst relative |Log(Exp(v)) - v|/|v|: quaternion " << worstQuat << ", matrix "
                                                           << worstMatrix << ", AngleAxis "
                                                           << worstAngleAxis);
}

TEST_CASE("Log stays accurate near pi", "[core][so3]") {
  real const offset = GENERATE(1e-3, 1e-6);
  real const angle = kPi - offset;
  CAPTURE(offset);
  std::mt19937 rng(7);
  for (int direction = 0; direction < 16; ++direction) {
    Real3 const axis = RandomUnit(rng);
    CAPTURE(axis.transpose());
    // the rotation from Eigen (independent of superdex::Exp), in both
    // quaternion signs and as a matrix
    Quat const q(Eigen::AngleAxis<real>(angle, axis));
    for (Real3 const& phi : {Log(q), Log(Quat(-q.coeffs())), Log(q.toRotationMatrix())}) {
      CAPTURE(phi.transpose());
      // the angle to a few ulps of π (absolute), the axis to a few ulps
      REQUIRE(std::abs(phi.norm() - angle) <= 8 * kEps * kPi);
      REQUIRE((phi.normalized() - axis).norm() <= kRoundTripTol);
    }
  }
}

TEST_CASE("Log at exactly pi returns an angle of pi and the same rotation", "[core][so3]") {
  std::mt19937 rng(11);
  for (int direction = 0; direction < 8; ++direction) {
    Real3 const axis = RandomUnit(rng);
    // w = 0 exactly: either sign of the axis is a valid answer
    Quat const q(0, axis.x(), axis.y(), axis.z());
    Real3 const phi = Log(q);
    CAPTURE(axis.transpose(), phi.transpose());
    REQUIRE(std::abs(phi.norm() - kPi) <= 8 * kEps * kPi);
    REQUIRE(std::abs(std::abs(phi.normalized().dot(axis)) - 1) <= kRoundTripTol);
    REQUIRE(MaxAbs(ExpMatrix(phi) - q.toRotationMatrix()) <= kMatrixTol);
  }
}

TEST_CASE("Exp inverts Log on random rotations", "[core][so3]") {
  std::mt19937 rng(3);
  for (int sample = 0; sample < 200; ++sample) {
    Quat const q = RandomQuat(rng);  // both hemispheres of w
    CAPTURE(q.coeffs().transpose());
    Real3 const phi = Log(q);
    REQUIRE(phi.norm() <= kPi * (1 + kEps));
    // Exp(Log(q)) is q up to sign: the same rotation matrix
    REQUIRE(MaxAbs(ExpMatrix(phi) - q.toRotationMatrix()) <= kMatrixTol);
    REQUIRE(std::abs(std::abs(Exp(phi).coeffs().dot(q.coeffs())) - 1) <= kMatrixTol);
    // and through the matrix overload of Log
    REQUIRE(MaxAbs(ExpMatrix(Log(q.toRotationMatrix())) - q.toRotationMatrix()) <= kMatrixTol);
  }
}

TEST_CASE("Log of a quaternion and of its negative agree", "[core][so3]") {
  std::mt19937 rng(5);
  DynamicArray<Quat> quats;
  for (int sample = 0; sample < 100; ++sample) quats.push_back(RandomQuat(rng));
  // and the hard cases: w tiny of either sign (angle near π), w near ±1
  Real3 const axis = RandomUnit(rng);
  for (real w : {1e-7, -1e-7, 1e-12, -1e-12, 1 - 1e-12, -(1 - 1e-12)}) {
    real const s = std::sqrt(1 - w * w);
    quats.emplace_back(w, s * axis.x(), s * axis.y(), s * axis.z());
  }
  for (Quat const& q : quats) {
    CAPTURE(q.coeffs().transpose());
    Real3 const a = Log(q);
    Real3 const b = Log(Quat(-q.coeffs()));
    CAPTURE(a.transpose(), b.transpose());
    REQUIRE(a.norm() > 0);
    REQUIRE((a - b).norm() <= 4 * kEps * a.norm());
  }
}

TEST_CASE("SO(3) Jacobians match central differences of their defining relations",
          "[core][so3][derivatives]") {
  // magnitudes asked for, plus the series switch of the Jacobian
  // coefficients at 1e-3 (both sides)
  real const magnitude =
      GENERATE(0.0, 1e-8, 1e-4, 1e-3 * (1 - 1e-9), 1e-3 * (1 + 1e-9), 0.5, 2.0, kPi - 1e-3);
  int const directionSeed = GENERATE(1, 2, 3);
  std::mt19937 rng(directionSeed);
  Real3 const phi = magnitude * RandomUnit(rng);
  CAPTURE(magnitude, phi.transpose());

  auto check = [](Real33 const& analytic, Real33 const& fd) {
    CAPTURE(analytic, fd);
    REQUIRE(analytic.norm() > 0);
    REQUIRE(fd.norm() > 0);
    real const error = MaxScaledError(analytic, fd);
    CAPTURE(error);
    REQUIRE(error <= kJacobianTol);
  };

  SECTION("LeftJacobianInverse: d/dδ Log(Exp(δ) Exp(φ))") {
    check(LeftJacobianInverse(phi), FdLeftJacobianInverse(phi));
  }
  SECTION("RightJacobianInverse: d/dδ Log(Exp(φ) Exp(δ))") {
    check(RightJacobianInverse(phi), FdRightJacobianInverse(phi));
  }
  SECTION("LeftJacobian: d/dδ Log(Exp(φ + δ) Exp(φ)⁻¹)") {
    check(LeftJacobian(phi), FdLeftJacobian(phi));
  }
  SECTION("RightJacobian: d/dδ Log(Exp(φ)⁻¹ Exp(φ + δ))") {
    check(RightJacobian(phi), FdRightJacobian(phi));
  }
  SECTION("each Jacobian times its inverse is the identity") {
    Real33 const left = LeftJacobian(phi) * LeftJacobianInverse(phi);
    Real33 const right = RightJacobian(phi) * RightJacobianInverse(phi);
    Real33 const leftOther = LeftJacobianInverse(phi) * LeftJacobian(phi);
    CAPTURE(left, right);
    REQUIRE(MaxScaledError(left, Real33::Identity()) <= kInverseTol);
    REQUIRE(MaxScaledError(right, Real33::Identity()) <= kInverseTol);
    REQUIRE(MaxScaledError(leftOther, Real33::Identity()) <= kInverseTol);
    // J_r(φ) = J_l(−φ) = J_l(φ)ᵀ
    REQUIRE(MaxScaledError(RightJacobian(phi), LeftJacobian(phi).transpose()) <= kInverseTol);
    REQUIRE(MaxScaledError(RightJacobianInverse(phi), LeftJacobianInverse(phi).transpose()) <=
            kInverseTol);
  }
}

TEST_CASE("the Jacobian checks tell left from right and a Jacobian from its inverse",
          "[core][so3][derivatives]") {
  // At moderate angles the four Jacobians differ by far more than
  // kJacobianTol, so the comparisons above cannot pass for a swapped or
  // identity implementation.
  real const magnitude = GENERATE(0.5, 2.0, kPi - 1e-3);
  std::mt19937 rng(1);
  Real3 const phi = magnitude * RandomUnit(rng);
  CAPTURE(magnitude);
  Real33 const fdLeftInverse = FdLeftJacobianInverse(phi);
  Real33 const fdLeft = FdLeftJacobian(phi);
  real const margin = 1e3 * kJacobianTol;
  REQUIRE(MaxScaledError(RightJacobianInverse(phi), fdLeftInverse) > margin);
  REQUIRE(MaxScaledError(LeftJacobian(phi), fdLeftInverse) > margin);
  REQUIRE(MaxScaledError(Real33::Identity(), fdLeftInverse) > margin);
  REQUIRE(MaxScaledError(RightJacobian(phi), fdLeft) > margin);
  REQUIRE(MaxScaledError(LeftJacobianInverse(phi), fdLeft) > margin);
}

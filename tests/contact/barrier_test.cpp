// Contact barrier and friction (contact/barrier.h):
//
// (a) b(s): hand values, the limits at s → 0⁺ and s <= 0, zero at and beyond
//     s = 1, C² (and not C³) at s = 1, derivatives against central
//     differences;
// (b) the pair energy E = κ w d̂ b((sqrt(d²) − thickness)/d̂): a hand value,
//     inactive beyond d̂, infinite at penetration; gradient and exact Hessian
//     against central differences through every distance type, with
//     thickness, and with the edge–edge mollifier; the projected and
//     Gauss–Newton Hessians;
// (c) the friction ramp ρ: hand values, C¹ (indeed C²) at ḡ, ρ′ ∈ [0, 1],
//     ρ′/x regular at 0, derivatives against central differences;
// (d) the friction energy in u and through Tᵀ Γ: derivatives against central
//     differences, PSD Hessians, the Coulomb bound, rigid translations.
#include "test_support.h"
#include "contact/contact_test_support.h"

#include <superdex/contact/barrier.h>


#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <type_traits>

using namespace superdex;
using namespace superdex::contact;
using namespace superdex::test;

namespace {

constexpr real kInfinity = std::numeric_limits<real>::infinity();

// Central differences with a step of 1e-6 of the problem's length scale
// (1 for positions, ḡ for tangential displacements): for these smooth
// functions (b is C² at s = 1 and the configurations keep s in [1/3, 5/6],
// ρ is C² at ḡ) truncation and round-off errors are ~1e-9 relative to the
// largest entry of the analytic quantity (measured); the checks demand 1e-6
// of it, which each check requires to be non-zero. A wrong term errs by
// O(1) relative.
constexpr real kFdRelativeStep = 1e-6;
constexpr real kFdTol = 1e-6;

// `f` returns ValueGradientHessian<n> at x; its gradient is checked against
// central differences of its value, its Hessian against central differences
// of its gradient.
template <int n, class F>
void RequireDerivatives(F const& f, Vec<n> const& x, real step) {
  ValueGradientHessian<n> const at = f(x);
  CAPTURE(x.transpose());
  REQUIRE(MaxAbs(at.gradient) > 0);
  REQUIRE(MaxAbs(at.hessian) > 0);
  real const gradientError = RelativeError(
      at.gradient, CentralGradient<n>([&](Vec<n> const& y) { return f(y).value; }, x, step));
  real const hessianError = RelativeError(
      at.hessian, CentralJacobian<n>([&](Vec<n> const& y) { return f(y).gradient; }, x, step));
  CAPTURE(gradientError, hessianError);
  REQUIRE(gradientError <= kFdTol);
  REQUIRE(hessianError <= kFdTol);
}

// Well-conditioned random pairs (contact_test_support.h) as 12 coordinates
// (p, t0, t1, t2) or (ea0, ea1, eb0, eb1).
Vec<12> RandomPointTriangle(std::mt19937& rng) {
  std::array<Real3, 3> const t = RandomTriangle(rng);
  Real3 const p = RandomPointNear(rng, t);
  return Pack(p, t[0], t[1], t[2]);
}
Vec<12> RandomEdgePairCoordinates(std::mt19937& rng) {
  std::array<Real3, 4> const e = RandomEdgePair(rng);
  return Pack(e[0], e[1], e[2], e[3]);
}

// Barrier parameters that make the pair at squared distance d2 active with
// s = d/d̂ in [1/3, 5/6]: thickness a random fraction (up to half) of the
// distance, d̂ = d · U(1.2, 3).
BarrierParams ActiveParams(std::mt19937& rng, real d2) {
  BarrierParams params;
  real const r = std::sqrt(d2);
  params.thickness = Uniform(rng, 0, 0.5) * r;
  params.activationDistance = (r - params.thickness) * Uniform(rng, 1.2, 3);
  params.stiffnessArea = 1e5 * 1e-4;  // κ = 1e5 Pa on w = 1 cm²: 10 N/m
  return params;
}


template <int n>
real MinEigenvalue(Mat<n> const& a) {
  return SymmetricEigenvalues(a).minCoeff();
}

}  // namespace

// ---------------------------------------------------------------- (a)

TEST_CASE("Barrier b(s): hand values, limits at 0+ and at s <= 0, zero from s = 1 on",
          "[contact][barrier]") {
  // s = 1/2: b = ¼ ln 2, b′ = −ln 2 − ½, b″ = 2 ln 2 + 5
  real const ln2 = std::log(2.0);
  REQUIRE(Near(Barrier(0.5), 0.25 * ln2, 1e-15));
  REQUIRE(Near(BarrierDerivative(0.5), -ln2 - 0.5, 1e-15));
  REQUIRE(Near(BarrierSecondDerivative(0.5), 2 * ln2 + 5, 1e-15));
  // s = 1 and beyond: exactly zero
  for (real s : {1.0, 1.0 + 1e-12, 2.0, 1e9}) {
    CAPTURE(s);
    REQUIRE(Barrier(s) == 0);
    REQUIRE(BarrierDerivative(s) == 0);
    REQUIRE(BarrierSecondDerivative(s) == 0);
  }
  // s → 0⁺: b ~ −ln s (b/(−ln s) = (1 − s)² → 1), b′ ~ −1/s, b″ ~ 1/s²
  for (real s : {1e-6, 1e-9, 1e-12, 1e-300}) {
    CAPTURE(s);
    REQUIRE(Near(Barrier(s) / -std::log(s), (1 - s) * (1 - s), 1e-14));
    REQUIRE(Near(BarrierDerivative(s) * s, -1, 1e-4));
    REQUIRE(Near(BarrierSecondDerivative(s) * s * s, 1, 1e-4));
  }
  // at and below zero: the limits
  for (real s : {0.0, -1e-12, -3.0}) {
    CAPTURE(s);
    REQUIRE(Barrier(s) == kInfinity);
    REQUIRE(BarrierDerivative(s) == -kInfinity);
    REQUIRE(BarrierSecondDerivative(s) == kInfinity);
  }
  // on (0, 1): b > 0 decreasing and convex
  real previous = kInfinity;
  for (int i = 1; i < 1000; ++i) {
    real const s = i / 1000.0;
    CAPTURE(s);
    REQUIRE(Barrier(s) > 0);
    REQUIRE(Barrier(s) < previous);
    REQUIRE(BarrierDerivative(s) < 0);
    REQUIRE(BarrierSecondDerivative(s) > 0);
    previous = Barrier(s);
  }
}

TEST_CASE("Barrier derivatives match central differences on (0, 1)", "[contact][barrier]") {
  for (int i = 1; i < 100; ++i) {
    real const s = i / 100.0, h = kFdRelativeStep * s;
    CAPTURE(s);
    real const fd1 = (Barrier(s + h) - Barrier(s - h)) / (2 * h);
    real const fd2 = (BarrierDerivative(s + h) - BarrierDerivative(s - h)) / (2 * h);
    REQUIRE(std::abs(fd1 - BarrierDerivative(s)) <= kFdTol * std::abs(BarrierDerivative(s)));
    REQUIRE(std::abs(fd2 - BarrierSecondDerivative(s)) <=
            kFdTol * std::abs(BarrierSecondDerivative(s)));
  }
}

TEST_CASE("Barrier is C2 at s = 1 but not C3 (b''' jumps from -6 to 0)", "[contact][barrier]") {
  // Taylor at s = 1 from below, b‴(1) = −6: b(1 − h) ≈ h³, b′(1 − h) ≈ −3h²,
  // b″(1 − h) ≈ 6h, each to relative O(h); from above all are 0.
  for (real h : {1e-2, 1e-3, 1e-4}) {
    CAPTURE(h);
    REQUIRE(std::abs(Barrier(1 - h) / (h * h * h) - 1) <= 2 * h);
    REQUIRE(std::abs(BarrierDerivative(1 - h) / (-3 * h * h) - 1) <= 2 * h);
    REQUIRE(std::abs(BarrierSecondDerivative(1 - h) / (6 * h) - 1) <= 2 * h);
    REQUIRE(BarrierSecondDerivative(1 + h) == 0);
  }
}

// ---------------------------------------------------------------- (b)

TEST_CASE(
    "Barrier energy: hand value with thickness, inactive beyond d-hat, infinite at penetration",
    "[contact][barrier]") {
  // points 0.5 apart, thickness 0.1, d̂ = 1, κ w = 10 N/m: d = 0.4, s = 0.4,
  // E = 10 · 1 · (−0.36 ln 0.4); ∂E/∂p1 = κ w b′(0.4) x̂ (dE/dd along the gap)
  Real3 const p0(0, 0, 0), p1(0.5, 0, 0);
  ValueGradientHessian<6> d2;
  d2.value = PointPointDistance2(p0, p1);
  d2.gradient = PointPointDistance2Gradient(p0, p1);
  d2.hessian = PointPointDistance2Hessian(p0, p1);
  BarrierParams params;
  params.thickness = 0.1;
  params.activationDistance = 1;
  params.stiffnessArea = 10;
  ValueGradientHessian<6> const e = BarrierEnergy(d2, params, BarrierHessian::Exact);
  REQUIRE(Near(e.value, -3.6 * std::log(0.4), 1e-14));
  real const b1 = -2 * (0.4 - 1) * std::log(0.4) - 0.36 / 0.4;
  REQUIRE(Near(e.gradient[3], 10 * b1, 1e-14));
  REQUIRE(Near(e.gradient[0], -10 * b1, 1e-14));
  REQUIRE(MaxAbs(Vec<4>(e.gradient[1], e.gradient[2], e.gradient[4], e.gradient[5])) == 0);

  SECTION("d >= d-hat: zero energy, gradient and Hessian") {
    for (real thickness : {0.0, 0.3}) {  // d = 0.5 − thickness >= d̂ = 0.5 − thickness
      params.thickness = thickness;
      params.activationDistance = 0.5 - thickness;
      for (BarrierHessian form :
           {BarrierHessian::Exact, BarrierHessian::Projected, BarrierHessian::GaussNewton}) {
        ValueGradientHessian<6> const zero = BarrierEnergy(d2, params, form);
        REQUIRE(zero.value == 0);
        REQUIRE(MaxAbs(zero.gradient) == 0);
        REQUIRE(MaxAbs(zero.hessian) == 0);
      }
    }
  }
  SECTION("d <= 0: infinite energy, finite (zero) gradient and Hessian") {
    params.activationDistance = 1;
    for (real thickness : {0.5, 0.7}) {
      params.thickness = thickness;
      ValueGradientHessian<6> const inf = BarrierEnergy(d2, params, BarrierHessian::Exact);
      REQUIRE(inf.value == kInfinity);
      REQUIRE(MaxAbs(inf.gradient) == 0);
      REQUIRE(MaxAbs(inf.hessian) == 0);
    }
    params.thickness = 0;
    d2.value = 0;  // coincident points
    REQUIRE(BarrierEnergy(d2, params, BarrierHessian::Exact).value == kInfinity);
  }
}

TEST_CASE(
    "Barrier energy: gradient and exact Hessian match central differences through every distance "
    "type",
    "[contact][barrier]") {
  // The distance type is held fixed while differencing. Thickness up to half
  // the distance; s ∈ [1/3, 5/6] (ActiveParams).
  SECTION("point-triangle, every type") {
    std::mt19937 rng(71);
    std::map<int, int> checked;
    for (int draws = 0; draws < 100000 && !AllReached(checked, 7, 4); ++draws) {
      Vec<12> const x = RandomPointTriangle(rng);
      auto const type = PointTriangleDistanceType(Node(x, 0), Node(x, 1), Node(x, 2), Node(x, 3));
      real const d2 = PointTriangleDistance2(Node(x, 0), Node(x, 1), Node(x, 2), Node(x, 3), type);
      if (d2 < 0.01 || checked[static_cast<int>(type)] >= 4) continue;
      ++checked[static_cast<int>(type)];
      BarrierParams const params = ActiveParams(rng, d2);
      CAPTURE(static_cast<int>(type), params.thickness, params.activationDistance);
      RequireDerivatives<12>(
          [&](Vec<12> const& y) {
            return BarrierEnergy(PointTriangleDistance2Derivatives(Node(y, 0), Node(y, 1),
                                                                   Node(y, 2), Node(y, 3), type),
                                 params, BarrierHessian::Exact);
          },
          x, kFdRelativeStep);
    }
    REQUIRE(AllReached(checked, 7, 4));
  }
  SECTION("edge-edge, every type, and mollified") {
    std::mt19937 rng(72);
    std::map<int, int> checked;
    for (int draws = 0; draws < 100000 && !AllReached(checked, 9, 4); ++draws) {
      Vec<12> const x = RandomEdgePairCoordinates(rng);
      auto const type = EdgeEdgeDistanceType(Node(x, 0), Node(x, 1), Node(x, 2), Node(x, 3));
      real const d2 = EdgeEdgeDistance2(Node(x, 0), Node(x, 1), Node(x, 2), Node(x, 3), type);
      if (d2 < 0.01 || checked[static_cast<int>(type)] >= 4) continue;
      ++checked[static_cast<int>(type)];
      BarrierParams const params = ActiveParams(rng, d2);
      // a mollifier threshold above c, so that m < 1 varies
      real const threshold =
          2 * EdgeEdgeCrossSquaredNorm(Node(x, 0), Node(x, 1), Node(x, 2), Node(x, 3));
      CAPTURE(static_cast<int>(type), params.thickness, params.activationDistance);
      auto barrier = [&](Vec<12> const& y) {
        return BarrierEnergy(
            EdgeEdgeDistance2Derivatives(Node(y, 0), Node(y, 1), Node(y, 2), Node(y, 3), type),
            params, BarrierHessian::Exact);
      };
      RequireDerivatives<12>(barrier, x, kFdRelativeStep);
      RequireDerivatives<12>(
          [&](Vec<12> const& y) {
            return Multiply(EdgeEdgeMollifierDerivatives(Node(y, 0), Node(y, 1), Node(y, 2),
                                                         Node(y, 3), threshold),
                            barrier(y));
          },
          x, kFdRelativeStep);
    }
    REQUIRE(AllReached(checked, 9, 4));
  }
  SECTION("point-edge and point-point") {
    std::mt19937 rng(73);
    int checked = 0;
    for (int draws = 0; draws < 100000 && checked < 20; ++draws) {
      Vec<9> x;
      x << RandomPoint(rng), RandomPoint(rng), RandomPoint(rng);
      auto const type = PointEdgeDistanceType(Node(x, 0), Node(x, 1), Node(x, 2));
      real const d2 = PointEdgeDistance2(Node(x, 0), Node(x, 1), Node(x, 2), type);
      if (d2 < 0.01 || (Node(x, 2) - Node(x, 1)).norm() < 0.3) continue;
      ++checked;
      BarrierParams const params = ActiveParams(rng, d2);
      CAPTURE(static_cast<int>(type));
      RequireDerivatives<9>(
          [&](Vec<9> const& y) {
            return BarrierEnergy(
                PointEdgeDistance2Derivatives(Node(y, 0), Node(y, 1), Node(y, 2), type), params,
                BarrierHessian::Exact);
          },
          x, kFdRelativeStep);
      Vec<6> const xp = x.head<6>();
      BarrierParams const pointParams =
          ActiveParams(rng, PointPointDistance2(Node(xp, 0), Node(xp, 1)));
      RequireDerivatives<6>(
          [&](Vec<6> const& y) {
            ValueGradientHessian<6> d2pp;
            d2pp.value = PointPointDistance2(Node(y, 0), Node(y, 1));
            d2pp.gradient = PointPointDistance2Gradient(Node(y, 0), Node(y, 1));
            d2pp.hessian = PointPointDistance2Hessian(Node(y, 0), Node(y, 1));
            return BarrierEnergy(d2pp, pointParams, BarrierHessian::Exact);
          },
          xp, kFdRelativeStep);
    }
    REQUIRE(checked == 20);
  }
}

TEST_CASE(
    "Projected and Gauss-Newton barrier Hessians are PSD and differ from the exact one as stated",
    "[contact][barrier]") {
  // Projected: P = V max(Λ, 0) Vᵀ of the exact H = V Λ Vᵀ, so P is PSD, P − H
  // is PSD with largest eigenvalue −λ_min(H), and P = H when H is PSD.
  // Gauss–Newton: G = φ″ ∇q∇qᵀ is PSD of rank one, and H − G = φ′ ∇²q with
  // φ′ = ∇E·∇q/‖∇q‖² read from the gradient (checked above by differences).
  // Eigenvalue tolerances: 1e-10 of the largest entry (the eigensolver is
  // backward stable to ~1e-15 of ‖H‖).
  std::mt19937 rng(74);
  int checked = 0, indefinite = 0;
  for (int k = 0; k < 200; ++k) {
    Vec<12> const x = RandomPointTriangle(rng);
    auto const type = PointTriangleDistanceType(Node(x, 0), Node(x, 1), Node(x, 2), Node(x, 3));
    ValueGradientHessian<12> const d2 =
        PointTriangleDistance2Derivatives(Node(x, 0), Node(x, 1), Node(x, 2), Node(x, 3), type);
    if (d2.value < 1e-4) continue;  // a point on the triangle's plane: d̂ would be ~0
    ++checked;
    BarrierParams const params = ActiveParams(rng, d2.value);
    CAPTURE(k, static_cast<int>(type));
    ValueGradientHessian<12> const exact = BarrierEnergy(d2, params, BarrierHessian::Exact);
    ValueGradientHessian<12> const projected = BarrierEnergy(d2, params, BarrierHessian::Projected);
    ValueGradientHessian<12> const gaussNewton =
        BarrierEnergy(d2, params, BarrierHessian::GaussNewton);
    real const scale = MaxAbs(exact.hessian);
    REQUIRE(scale > 0);
    REQUIRE(projected.value == exact.value);
    REQUIRE(projected.gradient == exact.gradient);
    REQUIRE(gaussNewton.gradient == exact.gradient);

    real const lambdaMin = MinEigenvalue<12>(exact.hessian);
    if (lambdaMin < -1e-6 * scale) ++indefinite;
    REQUIRE(MinEigenvalue<12>(projected.hessian) >= -1e-10 * scale);
    Mat<12> const added = projected.hessian - exact.hessian;
    REQUIRE(MinEigenvalue<12>(added) >= -1e-10 * scale);
    real const addedMax = SymmetricEigenvalues(added).maxCoeff();
    REQUIRE(std::abs(addedMax - std::max(-lambdaMin, real(0))) <= 1e-10 * scale);
    if (lambdaMin >= 0) REQUIRE(projected.hessian == exact.hessian);

    REQUIRE(MinEigenvalue<12>(gaussNewton.hessian) >= -1e-10 * scale);
    REQUIRE(SymmetricEigenvalues(gaussNewton.hessian)[10] <= 1e-10 * scale);  // rank one
    real const slope = exact.gradient.dot(d2.gradient) / d2.gradient.squaredNorm();
    REQUIRE(slope < 0);
    REQUIRE(MaxAbs(exact.hessian - gaussNewton.hessian - slope * d2.hessian) <= 1e-12 * scale);
  }
  REQUIRE(checked >= 190);
  // the projection did something in a good share of the configurations
  REQUIRE(indefinite >= 20);
}

// ---------------------------------------------------------------- (c)

TEST_CASE("Friction ramp: hand values, C1 (and C2) at the saturation, rho' in [0, 1]",
          "[contact][friction]") {
  real const g = 2e-3;  // ḡ [m]
  // x = ḡ/2: ρ = ḡ/4 − ḡ/24 = 5ḡ/24, ρ′ = 3/4, ρ″ = 1/ḡ, ρ′/x = 3/(2ḡ)
  REQUIRE(Near(FrictionRamp(g / 2, g) / g, 5.0 / 24, 1e-15));
  REQUIRE(Near(FrictionRampDerivative(g / 2, g), 0.75, 1e-15));
  REQUIRE(Near(FrictionRampSecondDerivative(g / 2, g) * g, 1, 1e-15));
  REQUIRE(Near(FrictionRampDerivativeOverX(g / 2, g) * g, 1.5, 1e-15));
  // x = 3ḡ: ρ = 3ḡ − ḡ/3, ρ′ = 1, ρ″ = 0, ρ′/x = 1/(3ḡ)
  REQUIRE(Near(FrictionRamp(3 * g, g) / g, 3 - 1.0 / 3, 1e-15));
  REQUIRE(FrictionRampDerivative(3 * g, g) == 1);
  REQUIRE(FrictionRampSecondDerivative(3 * g, g) == 0);
  REQUIRE(Near(FrictionRampDerivativeOverX(3 * g, g) * g, 1.0 / 3, 1e-15));
  // x = 0: ρ = ρ′ = 0, ρ″ = ρ′/x = 2/ḡ
  REQUIRE(FrictionRamp(0, g) == 0);
  REQUIRE(FrictionRampDerivative(0, g) == 0);
  REQUIRE(Near(FrictionRampSecondDerivative(0, g) * g, 2, 1e-15));
  REQUIRE(Near(FrictionRampDerivativeOverX(0, g) * g, 2, 1e-15));

  // at ḡ ± δ: ρ = 2ḡ/3 ∓ δ(1 + O(δ/ḡ)), ρ′ = 1 − O(δ²/ḡ²), ρ″ = O(δ/ḡ²)
  for (real delta : {1e-4 * g, 1e-7 * g}) {
    CAPTURE(delta);
    real const below = g - delta, above = g + delta;
    REQUIRE(std::abs(FrictionRamp(below, g) - 2 * g / 3) <= 1.01 * delta);
    REQUIRE(std::abs(FrictionRamp(above, g) - 2 * g / 3) <= 1.01 * delta);
    REQUIRE(std::abs(FrictionRampDerivative(below, g) - FrictionRampDerivative(above, g)) <=
            2 * (delta / g) * (delta / g));
    REQUIRE(std::abs(FrictionRampSecondDerivative(below, g) -
                     FrictionRampSecondDerivative(above, g)) <= 3 * delta / (g * g));
  }
  // ρ′ ∈ [0, 1] and non-decreasing, ρ″ >= 0; ρ′/x = ρ′(x)/x away from 0
  real previous = 0;
  for (int i = 0; i <= 10000; ++i) {
    real const x = i * (10 * g / 10000);
    real const slope = FrictionRampDerivative(x, g);
    CAPTURE(x);
    REQUIRE(slope >= 0);
    REQUIRE(slope <= 1);
    REQUIRE(slope >= previous);
    REQUIRE(FrictionRampSecondDerivative(x, g) >= 0);
    if (i > 0) REQUIRE(Near(FrictionRampDerivativeOverX(x, g) * g, slope / x * g, 1e-13));
    previous = slope;
  }
}

TEST_CASE("Friction ramp derivatives match central differences", "[contact][friction]") {
  real const g = 2e-3, h = kFdRelativeStep * g;
  for (int i = 1; i < 300; ++i) {
    real const x = i * (3 * g / 300);
    CAPTURE(x);
    real const fd1 = (FrictionRamp(x + h, g) - FrictionRamp(x - h, g)) / (2 * h);
    real const fd2 =
        (FrictionRampDerivative(x + h, g) - FrictionRampDerivative(x - h, g)) / (2 * h);
    // ρ′ is O(1), ρ″ O(1/ḡ): errors relative to those scales
    REQUIRE(std::abs(fd1 - FrictionRampDerivative(x, g)) <= kFdTol);
    REQUIRE(std::abs(fd2 - FrictionRampSecondDerivative(x, g)) <= kFdTol / g);
  }
}

// ---------------------------------------------------------------- (d)

TEST_CASE("Tangential friction in u: derivatives, PSD Hessian, Coulomb bound, regular at u = 0",
          "[contact][friction]") {
  real const g = 1e-3, muLambda = 0.4 * 25;  // μ = 0.4, λ = 25 N
  std::mt19937 rng(81);
  for (int k = 0; k < 200; ++k) {
    // |u| log-uniform in [1e-4 ḡ, 3ḡ], both sides of ḡ
    real const magnitude = g * std::pow(10.0, Uniform(rng, -4, std::log10(3.0)));
    real const angle = Uniform(rng, 0, 6.283185307179586);
    Vector2 const u = magnitude * Vector2(std::cos(angle), std::sin(angle));
    CAPTURE(k, u.transpose());
    RequireDerivatives<2>(
        [&](Vector2 const& v) {
          TangentialFriction const f = EvaluateTangentialFriction(v, muLambda, g);
          ValueGradientHessian<2> r;
          r.value = f.energy;
          r.gradient = f.gradient;
          r.hessian = f.hessian;
          return r;
        },
        u, kFdRelativeStep * g);
    TangentialFriction const f = EvaluateTangentialFriction(u, muLambda, g);
    // eigenvalues μλρ″ (along u) and μλρ′/x (across): PSD
    Vector2 const eigenvalues = SymmetricEigenvalues(f.hessian);
    real const radial = muLambda * FrictionRampSecondDerivative(magnitude, g);
    real const across = muLambda * FrictionRampDerivativeOverX(magnitude, g);
    REQUIRE(Near(eigenvalues[0] * g, std::min(radial, across) * g, 1e-12));
    REQUIRE(Near(eigenvalues[1] * g, std::max(radial, across) * g, 1e-12));
    REQUIRE(eigenvalues[0] >= -1e-12 * eigenvalues[1]);  // 0 beyond ḡ, up to round-off
    // the force magnitude μλρ′ never exceeds μλ, and reaches it beyond ḡ
    REQUIRE(f.gradient.norm() <= muLambda * (1 + 1e-15));
    if (magnitude >= g) REQUIRE(Near(f.gradient.norm(), muLambda, 1e-15));
  }
  // at u = 0 (and at a denormal u) the Hessian is (2μλ/ḡ) I, energy and force 0
  for (Vector2 const& u : {Vector2(0, 0), Vector2(1e-310, -1e-310)}) {
    TangentialFriction const f = EvaluateTangentialFriction(u, muLambda, g);
    REQUIRE(f.energy <= 1e-300);
    REQUIRE(f.gradient.norm() <= 1e-300);
    REQUIRE(f.hessian.allFinite());
    REQUIRE(MaxAbs(f.hessian - (2 * muLambda / g) * Matrix2::Identity()) <=
            1e-12 * (2 * muLambda / g));
  }
}

TEST_CASE("Friction energy through T^T Gamma: derivatives, PSD, no cost for rigid translations",
          "[contact][friction]") {
  real const g = 1e-3, muLambda = 0.3 * 40;
  std::mt19937 rng(82);
  auto randomDisplacement = [&](auto& dx) {
    for (int i = 0; i < dx.size(); ++i) dx[i] = Uniform(rng, -2 * g, 2 * g);
  };
  auto checkFrame = [&](auto const& frame, auto const& dx) {
    constexpr int n = std::remove_reference_t<decltype(dx)>::RowsAtCompileTime;
    auto energy = [&](Vec<n> const& y) { return FrictionEnergy<n>(y, frame, muLambda, g); };
    RequireDerivatives<n>(energy, dx, kFdRelativeStep * g);
    ValueGradientHessian<n> const at = energy(dx);
    REQUIRE(MinEigenvalue<n>(at.hessian) >= -1e-12 * MaxAbs(at.hessian));
    // the two building blocks give the same
    Vector2 const u = frame.basis.transpose() * (frame.weights * dx);
    ValueGradientHessian<n> const mapped =
        MapTangentialFriction<n>(EvaluateTangentialFriction(u, muLambda, g), frame);
    REQUIRE(mapped.value == at.value);
    REQUIRE(MaxAbs(mapped.gradient - at.gradient) == 0);
    // a rigid translation moves neither point relative to the other
    Vec<n> translation;
    for (int i = 0; i < n / 3; ++i)
      translation.template segment<3>(3 * i) = Real3(0.4, -0.2, 0.9) * g;
    ValueGradientHessian<n> const rigid = energy(translation);
    REQUIRE(std::abs(rigid.value) <= 1e-15 * muLambda * g);
    REQUIRE(MaxAbs(rigid.gradient) <= 1e-12 * muLambda);
  };
  std::map<int, int> seenPt, seenEe;
  for (int k = 0; k < 60; ++k) {
    CAPTURE(k);
    Vec<12> const pt = RandomPointTriangle(rng);
    auto const ptType =
        PointTriangleDistanceType(Node(pt, 0), Node(pt, 1), Node(pt, 2), Node(pt, 3));
    ++seenPt[static_cast<int>(ptType)];
    Vec<12> dx;
    randomDisplacement(dx);
    checkFrame(
        PointTriangleTangentFrame(Node(pt, 0), Node(pt, 1), Node(pt, 2), Node(pt, 3), ptType), dx);

    Vec<12> const ee = RandomEdgePairCoordinates(rng);
    auto const eeType = EdgeEdgeDistanceType(Node(ee, 0), Node(ee, 1), Node(ee, 2), Node(ee, 3));
    ++seenEe[static_cast<int>(eeType)];
    randomDisplacement(dx);
    checkFrame(EdgeEdgeTangentFrame(Node(ee, 0), Node(ee, 1), Node(ee, 2), Node(ee, 3), eeType),
               dx);

    Vec<9> dx9;
    randomDisplacement(dx9);
    auto const peType = PointEdgeDistanceType(Node(pt, 0), Node(pt, 1), Node(pt, 2));
    checkFrame(PointEdgeTangentFrame(Node(pt, 0), Node(pt, 1), Node(pt, 2), peType), dx9);

    Vec<6> dx6;
    randomDisplacement(dx6);
    TangentFrame<6> pp;
    pp.basis = PointPointTangentBasis(Node(pt, 0), Node(pt, 1));
    pp.weights = PointPointDisplacementWeights();
    checkFrame(pp, dx6);
  }
  REQUIRE(seenPt.size() >= 5);
  REQUIRE(seenEe.size() >= 5);
}

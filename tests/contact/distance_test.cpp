// Contact distances (contact/distance.h):
//
// (a) the four smooth squared distances against independent references
//     (Eigen's ParametrizedLine and Hyperplane, a QR least-squares solve for
//     two lines), and their gradients and Hessians against central
//     differences;
// (b) the classification: the classified distance is the distance between
//     the closed primitives, checked exactly by the projection inequality
//     (the closest point c of a convex set K to p satisfies
//     (p − c)·(y − c) <= 0 for every vertex y of K) and independently by
//     dense sampling; every type is reached;
// (c) the type-dispatched distances' derivatives against central
//     differences for every type;
// (d) degenerate inputs: parallel, nearly parallel and collinear edges,
//     zero-length edges, points on the triangle, collinear triangles;
// (e) the edge–edge mollifier, its derivatives and the product rule;
// (f) the tangent frames: orthonormal bases orthogonal to the contact
//     normal, weights Γ that give the vector between the closest points and
//     vanish on rigid translations.
//
// Positions are O(1) (random in [−1, 1]³), so squared distances and their
// derivatives are O(1) to O(100) after the conditioning filters below.
#include "test_support.h"
#include "contact/contact_test_support.h"

#include <superdex/contact/distance.h>

#include <Eigen/QR>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>

using namespace superdex;
using namespace superdex::contact;
using namespace superdex::test;

namespace {

// Central differences with step 1e-6 of functions of O(1) coordinates: the
// truncation error δ²/6 |f‴| stays below 1e-10 for the configurations kept
// (|f‴| <= ~1e2 once sines of angles are >= 0.2 and edges >= 0.3), the
// round-off error ε|f|/δ ~ 1e-10 (ε|∇f|/δ for the Hessian, against the
// analytic gradient). Measured errors are ~1e-9 relative to the largest entry;
// the checks demand 1e-6 of it (which each check requires to be non-zero).
// A wrong term in a derivative errs by O(1) relative.
constexpr real kFdStep = 1e-6;
constexpr real kFdTol = 1e-6;

// Squared distances compared with an independent formula: both are a few
// dozen flops on O(1) numbers, so agree to ~1e-15 relative to the squared
// scale; 1e-12 of max(value, 1) leaves three decades.
constexpr real kValueTol = 1e-12;

// The analytic gradient against central differences of `value`, the
// analytic Hessian against central differences of the analytic gradient;
// both non-zero and symmetric Hessian.
template <int n, class Value, class Gradient, class Hessian>
void RequireDerivatives(Value const& value, Gradient const& gradient, Hessian const& hessian,
                        Vec<n> const& x) {
  Vec<n> const g = gradient(x);
  Mat<n> const h = hessian(x);
  CAPTURE(x.transpose());
  REQUIRE(MaxAbs(g) > 0);
  REQUIRE(MaxAbs(h) > 0);
  real const gradientError = RelativeError(g, CentralGradient<n>(value, x, kFdStep));
  real const hessianError = RelativeError(h, CentralJacobian<n>(gradient, x, kFdStep));
  CAPTURE(gradientError, hessianError);
  REQUIRE(gradientError <= kFdTol);
  REQUIRE(hessianError <= kFdTol);
  REQUIRE(MaxAbs(h - h.transpose()) <= 1e-14 * MaxAbs(h));
}

// The squared distance from p to the closed segment (a, b) by sampling
// `samples` + 1 points; within (‖b − a‖/(2 samples))² of the truth in distance.
real SampledPointSegmentDistance(Real3 const& p, Real3 const& a, Real3 const& b, int samples) {
  real best = std::numeric_limits<real>::infinity();
  for (int i = 0; i <= samples; ++i)
    best = std::min(best, (p - (a + (b - a) * (real(i) / samples))).norm());
  return best;
}

int ToInt(PointTriangleType t) {
  return static_cast<int>(t);
}
int ToInt(EdgeEdgeType t) {
  return static_cast<int>(t);
}
int ToInt(PointEdgeType t) {
  return static_cast<int>(t);
}

}  // namespace

// ---------------------------------------------------------------- (a)

TEST_CASE("Smooth squared distances agree with independent geometric references",
          "[contact][distance]") {
  std::mt19937 rng(11);
  for (int k = 0; k < 200; ++k) {
    Real3 const a = RandomPoint(rng), b = RandomPoint(rng), c = RandomPoint(rng),
                d = RandomPoint(rng);
    CAPTURE(k);
    REQUIRE(Near(PointPointDistance2(a, b), (a - b).dot(a - b), kValueTol));

    real const line = Eigen::ParametrizedLine<real, 3>::Through(b, c).squaredDistance(a);
    REQUIRE(Near(PointLineDistance2(a, b, c), line, kValueTol));

    real const plane = Eigen::Hyperplane<real, 3>::Through(b, c, d).absDistance(a);
    REQUIRE(Near(PointPlaneDistance2(a, b, c, d), plane * plane, kValueTol));

    // the lines a + s(b − a), c + t(d − c): min ‖(a − c) + s(b − a) − t(d − c)‖² by QR
    Eigen::Matrix<real, 3, 2> m;
    m << b - a, -(d - c);
    Vector2 const st = m.colPivHouseholderQr().solve(Real3(c - a));
    real const lines = (m * st - (c - a)).squaredNorm();
    REQUIRE(Near(LineLineDistance2(a, b, c, d), lines, kValueTol));
  }
}

TEST_CASE("Smooth squared distances: gradients and Hessians match central differences",
          "[contact][distance]") {
  std::mt19937 rng(12);
  SECTION("point-point") {
    for (int k = 0; k < 50; ++k) {
      Vec<6> x;
      x << RandomPoint(rng), RandomPoint(rng);
      RequireDerivatives<6>(
          [](Vec<6> const& y) { return PointPointDistance2(Node(y, 0), Node(y, 1)); },
          [](Vec<6> const& y) { return PointPointDistance2Gradient(Node(y, 0), Node(y, 1)); },
          [](Vec<6> const& y) { return PointPointDistance2Hessian(Node(y, 0), Node(y, 1)); }, x);
    }
  }
  SECTION("point-line") {
    for (int k = 0; k < 50; ++k) {
      std::array<Real3, 3> const t = RandomTriangle(rng);
      Vec<9> x;
      x << t[0], t[1], t[2];
      RequireDerivatives<9>(
          [](Vec<9> const& y) { return PointLineDistance2(Node(y, 0), Node(y, 1), Node(y, 2)); },
          [](Vec<9> const& y) {
            return PointLineDistance2Gradient(Node(y, 0), Node(y, 1), Node(y, 2));
          },
          [](Vec<9> const& y) {
            return PointLineDistance2Hessian(Node(y, 0), Node(y, 1), Node(y, 2));
          },
          x);
    }
  }
  SECTION("point-plane") {
    for (int k = 0; k < 50; ++k) {
      std::array<Real3, 3> const t = RandomTriangle(rng);
      Vec<12> const x = Pack(RandomPointNear(rng, t), t[0], t[1], t[2]);
      RequireDerivatives<12>(
          [](Vec<12> const& y) {
            return PointPlaneDistance2(Node(y, 0), Node(y, 1), Node(y, 2), Node(y, 3));
          },
          [](Vec<12> const& y) {
            return PointPlaneDistance2Gradient(Node(y, 0), Node(y, 1), Node(y, 2), Node(y, 3));
          },
          [](Vec<12> const& y) {
            return PointPlaneDistance2Hessian(Node(y, 0), Node(y, 1), Node(y, 2), Node(y, 3));
          },
          x);
    }
  }
  SECTION("line-line") {
    for (int k = 0; k < 50; ++k) {
      std::array<Real3, 4> const e = RandomEdgePair(rng);
      Vec<12> const x = Pack(e[0], e[1], e[2], e[3]);
      RequireDerivatives<12>(
          [](Vec<12> const& y) {
            return LineLineDistance2(Node(y, 0), Node(y, 1), Node(y, 2), Node(y, 3));
          },
          [](Vec<12> const& y) {
            return LineLineDistance2Gradient(Node(y, 0), Node(y, 1), Node(y, 2), Node(y, 3));
          },
          [](Vec<12> const& y) {
            return LineLineDistance2Hessian(Node(y, 0), Node(y, 1), Node(y, 2), Node(y, 3));
          },
          x);
    }
  }
}

// ---------------------------------------------------------------- (b)

TEST_CASE("Point-triangle classification yields the distance to the closed triangle",
          "[contact][distance]") {
  // The closest point c = t0 + β1 (t1 − t0) + β2 (t2 − t0) is read from the
  // type's frame (Γ = [I, −(1−β1−β2)I, −β1 I, −β2 I]). Exact checks, to
  // round-off (1e-12 of the O(1) squared scale): c in the closed triangle,
  // ‖p − c‖² the classified distance, and the projection inequality at the
  // three vertices. Sampling check: 5151 points of the triangle on a grid of
  // spacing 1/100 in barycentric coordinates; every point of the triangle is
  // within max edge/100 of one, so the sampled distance exceeds the true one
  // by at most that, and is never below it.
  constexpr real kExactTol = 1e-12;
  constexpr int kGrid = 100;
  std::mt19937 rng(21);
  std::map<int, int> seen;
  for (int k = 0; k < 700; ++k) {
    std::array<Real3, 3> const t = RandomTriangle(rng);
    Real3 const p = RandomPointNear(rng, t);
    PointTriangleType const type = PointTriangleDistanceType(p, t[0], t[1], t[2]);
    ++seen[ToInt(type)];
    CAPTURE(k, ToInt(type));

    real const distance2 = PointTriangleDistance2(p, t[0], t[1], t[2], type);
    REQUIRE(distance2 == PointTriangleDistance2(p, t[0], t[1], t[2]));
    Eigen::Matrix<real, 3, 12> const gamma =
        PointTriangleTangentFrame(p, t[0], t[1], t[2], type).weights;
    real const beta1 = -gamma(0, 6), beta2 = -gamma(0, 9);
    Real3 const c = t[0] + beta1 * (t[1] - t[0]) + beta2 * (t[2] - t[0]);
    REQUIRE(beta1 >= -kExactTol);
    REQUIRE(beta2 >= -kExactTol);
    REQUIRE(beta1 + beta2 <= 1 + kExactTol);
    REQUIRE(Near((p - c).squaredNorm(), distance2, kExactTol));
    for (Real3 const& y : t) REQUIRE((p - c).dot(y - c) <= kExactTol);

    real sampled = std::numeric_limits<real>::infinity();
    for (int i = 0; i <= kGrid; ++i)
      for (int j = 0; i + j <= kGrid; ++j) {
        Real3 const q =
            t[0] + (t[1] - t[0]) * (real(i) / kGrid) + (t[2] - t[0]) * (real(j) / kGrid);
        sampled = std::min(sampled, (p - q).norm());
      }
    real const maxEdge =
        std::max({(t[1] - t[0]).norm(), (t[2] - t[1]).norm(), (t[0] - t[2]).norm()});
    real const distance = std::sqrt(distance2);
    REQUIRE(distance <= sampled + kExactTol);
    REQUIRE(sampled <= distance + maxEdge / kGrid);
  }
  // every feature type was reached (the checks above are not vacuous)
  for (int type = 0; type < 7; ++type) {
    CAPTURE(type);
    REQUIRE(seen[type] >= 10);
  }
}

TEST_CASE("Edge-edge classification yields the distance between the closed segments",
          "[contact][distance]") {
  // Closest points ca = ea0 + α (ea1 − ea0), cb = eb0 + β (eb1 − eb0) from
  // the type's frame (Γ = [(1−α)I, αI, −(1−β)I, −βI]). Exact checks as for
  // the triangle, on the product of the two segments (convex): α, β ∈ [0, 1],
  // (ca − cb)·(x − ca) >= 0 for x = ea0, ea1 and (cb − ca)·(y − cb) >= 0 for
  // y = eb0, eb1. Sampling: 201 × 201 points; each segment's nearest sample is
  // within length/400, so the sampled distance exceeds the true one by at
  // most (‖a‖ + ‖b‖)/400.
  constexpr real kExactTol = 1e-12;
  constexpr int kSamples = 200;
  std::mt19937 rng(22);
  std::map<int, int> seen;
  for (int k = 0; k < 1500; ++k) {
    std::array<Real3, 4> const e = {RandomPoint(rng), RandomPoint(rng), RandomPoint(rng),
                                    RandomPoint(rng)};
    EdgeEdgeType const type = EdgeEdgeDistanceType(e[0], e[1], e[2], e[3]);
    ++seen[ToInt(type)];
    CAPTURE(k, ToInt(type));

    real const distance2 = EdgeEdgeDistance2(e[0], e[1], e[2], e[3], type);
    REQUIRE(distance2 == EdgeEdgeDistance2(e[0], e[1], e[2], e[3]));
    Eigen::Matrix<real, 3, 12> const gamma =
        EdgeEdgeTangentFrame(e[0], e[1], e[2], e[3], type).weights;
    real const alpha = gamma(0, 3), beta = -gamma(0, 9);
    REQUIRE(alpha >= -kExactTol);
    REQUIRE(alpha <= 1 + kExactTol);
    REQUIRE(beta >= -kExactTol);
    REQUIRE(beta <= 1 + kExactTol);
    Real3 const ca = e[0] + alpha * (e[1] - e[0]), cb = e[2] + beta * (e[3] - e[2]);
    REQUIRE(Near((ca - cb).squaredNorm(), distance2, kExactTol));
    REQUIRE((ca - cb).dot(e[0] - ca) >= -kExactTol);
    REQUIRE((ca - cb).dot(e[1] - ca) >= -kExactTol);
    REQUIRE((cb - ca).dot(e[2] - cb) >= -kExactTol);
    REQUIRE((cb - ca).dot(e[3] - cb) >= -kExactTol);

    if (k % 5 == 0) {  // sampling is the slow part: every fifth pair
      real sampled = std::numeric_limits<real>::infinity();
      for (int i = 0; i <= kSamples; ++i) {
        Real3 const qa = e[0] + (e[1] - e[0]) * (real(i) / kSamples);
        for (int j = 0; j <= kSamples; ++j)
          sampled = std::min(sampled, (qa - (e[2] + (e[3] - e[2]) * (real(j) / kSamples))).norm());
      }
      real const distance = std::sqrt(distance2);
      REQUIRE(distance <= sampled + kExactTol);
      REQUIRE(sampled <= distance + ((e[1] - e[0]).norm() + (e[3] - e[2]).norm()) / (2 * kSamples));
    }
  }
  for (int type = 0; type < 9; ++type) {
    CAPTURE(type);
    REQUIRE(seen[type] >= 10);
  }
}

TEST_CASE("Point-edge classification yields the distance to the closed segment",
          "[contact][distance]") {
  // as above; sampling with 2001 points, error at most length/4000
  constexpr real kExactTol = 1e-12;
  constexpr int kSamples = 2000;
  std::mt19937 rng(23);
  std::map<int, int> seen;
  for (int k = 0; k < 300; ++k) {
    Real3 const p = RandomPoint(rng), e0 = RandomPoint(rng), e1 = RandomPoint(rng);
    PointEdgeType const type = PointEdgeDistanceType(p, e0, e1);
    ++seen[ToInt(type)];
    CAPTURE(k, ToInt(type));
    real const distance2 = PointEdgeDistance2(p, e0, e1, type);
    REQUIRE(distance2 == PointEdgeDistance2(p, e0, e1));
    real const alpha = -PointEdgeTangentFrame(p, e0, e1, type).weights(0, 6);
    REQUIRE(alpha >= -kExactTol);
    REQUIRE(alpha <= 1 + kExactTol);
    Real3 const c = e0 + alpha * (e1 - e0);
    REQUIRE(Near((p - c).squaredNorm(), distance2, kExactTol));
    REQUIRE((p - c).dot(e0 - c) <= kExactTol);
    REQUIRE((p - c).dot(e1 - c) <= kExactTol);
    real const sampled = SampledPointSegmentDistance(p, e0, e1, kSamples);
    real const distance = std::sqrt(distance2);
    REQUIRE(distance <= sampled + kExactTol);
    REQUIRE(sampled <= distance + (e1 - e0).norm() / (2 * kSamples));
  }
  for (int type = 0; type < 3; ++type) {
    CAPTURE(type);
    REQUIRE(seen[type] >= 10);
  }
}

// ---------------------------------------------------------------- (c)

TEST_CASE("Type-dispatched squared distances: derivatives match central differences for every type",
          "[contact][distance]") {
  // The type is held fixed while differencing (as the Newton step does);
  // configurations are drawn until every type has had 8 checks.
  constexpr int kPerType = 8;
  SECTION("point-triangle") {
    std::mt19937 rng(31);
    std::map<int, int> checked;
    for (int draws = 0; draws < 100000 && !AllReached(checked, 7, kPerType); ++draws) {
      std::array<Real3, 3> const t = RandomTriangle(rng);
      Real3 const p = RandomPointNear(rng, t);
      PointTriangleType const type = PointTriangleDistanceType(p, t[0], t[1], t[2]);
      if (checked[ToInt(type)] >= kPerType) continue;
      ++checked[ToInt(type)];
      CAPTURE(ToInt(type));
      auto value = [type](Vec<12> const& y) {
        return PointTriangleDistance2(Node(y, 0), Node(y, 1), Node(y, 2), Node(y, 3), type);
      };
      auto gradient = [type](Vec<12> const& y) {
        return PointTriangleDistance2Gradient(Node(y, 0), Node(y, 1), Node(y, 2), Node(y, 3), type);
      };
      auto hessian = [type](Vec<12> const& y) {
        return PointTriangleDistance2Hessian(Node(y, 0), Node(y, 1), Node(y, 2), Node(y, 3), type);
      };
      Vec<12> const x = Pack(p, t[0], t[1], t[2]);
      RequireDerivatives<12>(value, gradient, hessian, x);
      // the three entry points agree with the all-in-one evaluation
      ValueGradientHessian<12> const all =
          PointTriangleDistance2Derivatives(p, t[0], t[1], t[2], type);
      REQUIRE(Near(all.value, value(x), kValueTol));
      REQUIRE(all.gradient == gradient(x));
      REQUIRE(all.hessian == hessian(x));
    }
    REQUIRE(AllReached(checked, 7, kPerType));
  }
  SECTION("edge-edge") {
    std::mt19937 rng(32);
    std::map<int, int> checked;
    for (int draws = 0; draws < 100000 && !AllReached(checked, 9, kPerType); ++draws) {
      std::array<Real3, 4> const e = RandomEdgePair(rng);
      EdgeEdgeType const type = EdgeEdgeDistanceType(e[0], e[1], e[2], e[3]);
      if (checked[ToInt(type)] >= kPerType) continue;
      ++checked[ToInt(type)];
      CAPTURE(ToInt(type));
      auto value = [type](Vec<12> const& y) {
        return EdgeEdgeDistance2(Node(y, 0), Node(y, 1), Node(y, 2), Node(y, 3), type);
      };
      auto gradient = [type](Vec<12> const& y) {
        return EdgeEdgeDistance2Gradient(Node(y, 0), Node(y, 1), Node(y, 2), Node(y, 3), type);
      };
      auto hessian = [type](Vec<12> const& y) {
        return EdgeEdgeDistance2Hessian(Node(y, 0), Node(y, 1), Node(y, 2), Node(y, 3), type);
      };
      RequireDerivatives<12>(value, gradient, hessian, Pack(e[0], e[1], e[2], e[3]));
    }
    REQUIRE(AllReached(checked, 9, kPerType));
  }
  SECTION("point-edge") {
    std::mt19937 rng(33);
    std::map<int, int> checked;
    for (int draws = 0; draws < 100000 && !AllReached(checked, 3, kPerType); ++draws) {
      std::array<Real3, 3> const t = RandomTriangle(rng);  // p, e0, e1 well separated
      PointEdgeType const type = PointEdgeDistanceType(t[0], t[1], t[2]);
      if (checked[ToInt(type)] >= kPerType) continue;
      ++checked[ToInt(type)];
      CAPTURE(ToInt(type));
      Vec<9> x;
      x << t[0], t[1], t[2];
      RequireDerivatives<9>(
          [type](Vec<9> const& y) {
            return PointEdgeDistance2(Node(y, 0), Node(y, 1), Node(y, 2), type);
          },
          [type](Vec<9> const& y) {
            return PointEdgeDistance2Gradient(Node(y, 0), Node(y, 1), Node(y, 2), type);
          },
          [type](Vec<9> const& y) {
            return PointEdgeDistance2Hessian(Node(y, 0), Node(y, 1), Node(y, 2), type);
          },
          x);
    }
    REQUIRE(AllReached(checked, 3, kPerType));
  }
}

// ---------------------------------------------------------------- (d)

TEST_CASE("Parallel and nearly parallel edges fall back to end-point types with finite derivatives",
          "[contact][distance]") {
  Real3 const ea0(0, 0, 0), ea1(1, 0, 0);
  auto requireFinite = [](Real3 const& a0, Real3 const& a1, Real3 const& b0, Real3 const& b1,
                          EdgeEdgeType type) {
    ValueGradientHessian<12> const d = EdgeEdgeDistance2Derivatives(a0, a1, b0, b1, type);
    REQUIRE(std::isfinite(d.value));
    REQUIRE(d.gradient.allFinite());
    REQUIRE(d.hessian.allFinite());
    TangentFrame<12> const frame = EdgeEdgeTangentFrame(a0, a1, b0, b1, type);
    REQUIRE(frame.basis.allFinite());
    REQUIRE(MaxAbs(frame.basis.transpose() * frame.basis - Matrix2::Identity()) <= 1e-14);
  };
  SECTION("exactly parallel, overlapping: the exact distance 0.3") {
    Real3 const eb0(0.25, 0.3, 0), eb1(1.5, 0.3, 0);
    EdgeEdgeType const type = EdgeEdgeDistanceType(ea0, ea1, eb0, eb1);
    CAPTURE(ToInt(type));
    REQUIRE(type != EdgeEdgeType::EA_EB);
    REQUIRE(Near(EdgeEdgeDistance2(ea0, ea1, eb0, eb1, type), 0.09, 1e-15));
    requireFinite(ea0, ea1, eb0, eb1, type);
    REQUIRE(EdgeEdgeCrossSquaredNorm(ea0, ea1, eb0, eb1) == 0);
    REQUIRE(EdgeEdgeMollifier(ea0, ea1, eb0, eb1, 1e-3) == 0);
  }
  SECTION("nearly parallel (1e-7 rad): not EA_EB, distance within 1e-7 of 0.3") {
    real const angle = 1e-7;
    Real3 const eb0(0.25, 0.3, 0);
    Real3 const eb1 = eb0 + 1.25 * Real3(std::cos(angle), 0, std::sin(angle));
    EdgeEdgeType const type = EdgeEdgeDistanceType(ea0, ea1, eb0, eb1);
    CAPTURE(ToInt(type));
    REQUIRE(type != EdgeEdgeType::EA_EB);
    // the lines are 0.3 apart; the end points used instead differ by <= 1.25e-7
    REQUIRE(std::abs(std::sqrt(EdgeEdgeDistance2(ea0, ea1, eb0, eb1, type)) - 0.3) <= 1.3e-7);
    requireFinite(ea0, ea1, eb0, eb1, type);
  }
  SECTION("above the parallel threshold (1e-3 rad, crossing): EA_EB, the line distance") {
    real const angle = 1e-3;
    Real3 const eb0(0.2, 0.3, -0.5e-3), eb1 = eb0 + Real3(std::cos(angle), 0, std::sin(angle));
    REQUIRE(EdgeEdgeDistanceType(ea0, ea1, eb0, eb1) == EdgeEdgeType::EA_EB);
    REQUIRE(Near(EdgeEdgeDistance2(ea0, ea1, eb0, eb1), 0.09, 1e-12));
  }
  SECTION("collinear, overlapping: zero distance") {
    Real3 const eb0(0.5, 0, 0), eb1(2, 0, 0);
    EdgeEdgeType const type = EdgeEdgeDistanceType(ea0, ea1, eb0, eb1);
    REQUIRE(type != EdgeEdgeType::EA_EB);
    REQUIRE(EdgeEdgeDistance2(ea0, ea1, eb0, eb1, type) == 0);
    requireFinite(ea0, ea1, eb0, eb1, type);
  }
  SECTION("collinear, disjoint: the gap between the facing end points") {
    Real3 const eb0(1.5, 0, 0), eb1(2, 0, 0);
    REQUIRE(EdgeEdgeDistanceType(ea0, ea1, eb0, eb1) == EdgeEdgeType::EA1_EB0);
    REQUIRE(Near(EdgeEdgeDistance2(ea0, ea1, eb0, eb1), 0.25, 1e-15));
  }
  SECTION("a zero-length edge is a point") {
    Real3 const eb(0.4, 0.5, 0.1);
    EdgeEdgeType const type = EdgeEdgeDistanceType(ea0, ea1, eb, eb);
    REQUIRE(type == EdgeEdgeType::EA_EB0);
    REQUIRE(Near(EdgeEdgeDistance2(ea0, ea1, eb, eb, type), 0.26, 1e-15));
    requireFinite(ea0, ea1, eb, eb, type);
    REQUIRE(PointEdgeDistanceType(ea1, eb, eb) == PointEdgeType::P_E0);
    REQUIRE(Near(PointEdgeDistance2(ea1, eb, eb), 0.36 + 0.25 + 0.01, 1e-15));
  }
}

TEST_CASE("Points on the triangle and degenerate triangles", "[contact][distance]") {
  Real3 const t0(0, 0, 0), t1(1, 0, 0), t2(0, 1, 0);
  SECTION("interior point: P_T, zero distance and gradient, Hessian 2 n n^T in p") {
    Real3 const p(0.2, 0.3, 0);
    REQUIRE(PointTriangleDistanceType(p, t0, t1, t2) == PointTriangleType::P_T);
    ValueGradientHessian<12> const d =
        PointTriangleDistance2Derivatives(p, t0, t1, t2, PointTriangleType::P_T);
    REQUIRE(d.value == 0);
    REQUIRE(MaxAbs(d.gradient) == 0);
    Real33 expected = Real33::Zero();
    expected(2, 2) = 2;
    REQUIRE(MaxAbs(d.hessian.topLeftCorner<3, 3>() - expected) <= 1e-15);
    REQUIRE(d.hessian.allFinite());
  }
  SECTION("point on an edge and on a vertex: zero distance") {
    for (Real3 const& p : {Real3(0.5, 0.5, 0), Real3(0.5, 0, 0), t1, t2}) {
      CAPTURE(p.transpose());
      PointTriangleType const type = PointTriangleDistanceType(p, t0, t1, t2);
      REQUIRE(PointTriangleDistance2(p, t0, t1, t2, type) <= 1e-32);
      REQUIRE(PointTriangleDistance2Hessian(p, t0, t1, t2, type).allFinite());
    }
  }
  SECTION("collinear vertices: never P_T, the distance to the segment they span") {
    Real3 const c0(0, 0, 0), c1(1, 0, 0), c2(2, 0, 0);
    std::mt19937 rng(41);
    for (int k = 0; k < 50; ++k) {
      Real3 const p = RandomPoint(rng, 3);
      PointTriangleType const type = PointTriangleDistanceType(p, c0, c1, c2);
      CAPTURE(k, ToInt(type));
      REQUIRE(type != PointTriangleType::P_T);
      real const reference =
          std::min({PointEdgeDistance2(p, c0, c2), PointEdgeDistance2(p, c0, c1)});
      REQUIRE(Near(PointTriangleDistance2(p, c0, c1, c2, type), reference, kValueTol));
      REQUIRE(PointTriangleDistance2Hessian(p, c0, c1, c2, type).allFinite());
      TangentFrame<12> const frame = PointTriangleTangentFrame(p, c0, c1, c2, type);
      REQUIRE(MaxAbs(frame.basis.transpose() * frame.basis - Matrix2::Identity()) <= 1e-14);
    }
  }
}

// ---------------------------------------------------------------- (e)

TEST_CASE("Edge-edge mollifier: threshold, values, C1 at the threshold and derivatives",
          "[contact][distance]") {
  SECTION("threshold and values") {
    // rest edges of lengths 2 and 3: ε× = 1e-3 · 4 · 9
    REQUIRE(Near(
        EdgeEdgeMollifierThreshold(Real3(0, 0, 0), Real3(2, 0, 0), Real3(1, 1, 1), Real3(1, 4, 1)),
        0.036, 1e-15));
    // unit edges at angle θ: c = sin²θ; with ε× = 2c, m = ½ (2 − ½) = 0.75
    real const theta = 0.1;
    Real3 const a0(0, 0, 0), a1(1, 0, 0), b0(0, 0, 1),
        b1 = b0 + Real3(std::cos(theta), std::sin(theta), 0);
    real const c = EdgeEdgeCrossSquaredNorm(a0, a1, b0, b1);
    REQUIRE(Near(c, std::sin(theta) * std::sin(theta), 1e-15));
    REQUIRE(Near(EdgeEdgeMollifier(a0, a1, b0, b1, 2 * c), 0.75, 1e-15));
    REQUIRE(Near(EdgeEdgeMollifierDerivatives(a0, a1, b0, b1, 2 * c).value, 0.75, 1e-15));
    // at and beyond the threshold: 1 with zero derivatives
    for (real threshold : {c, 0.5 * c, 0.0}) {
      ValueGradientHessian<12> const m = EdgeEdgeMollifierDerivatives(a0, a1, b0, b1, threshold);
      REQUIRE(m.value == 1);
      REQUIRE(MaxAbs(m.gradient) == 0);
      REQUIRE(MaxAbs(m.hessian) == 0);
    }
    // C¹ at c = ε×: with x = c/ε× = 1 − δ just below, 1 − m = δ² and
    // m′ = 2δ/ε×, so ∇m = m′∇c vanishes linearly in δ; against x = ½
    // (m′ = 1/ε×, ε× = 2c) the gradient is 4δ(1 − δ) times smaller
    for (real below : {1e-3, 1e-8}) {
      CAPTURE(below);
      ValueGradientHessian<12> const nearOne =
          EdgeEdgeMollifierDerivatives(a0, a1, b0, b1, c / (1 - below));
      ValueGradientHessian<12> const half = EdgeEdgeMollifierDerivatives(a0, a1, b0, b1, 2 * c);
      // (m itself is rounded to ~1e-16 near 1)
      REQUIRE(std::abs(1 - nearOne.value - below * below) <= 1e-6 * below * below + 1e-15);
      REQUIRE(MaxAbs(half.gradient) > 1);
      REQUIRE(Near(MaxAbs(nearOne.gradient) / MaxAbs(half.gradient), 4 * below * (1 - below),
                   1e-6 * below));
    }
  }
  SECTION("gradient and Hessian against central differences (threshold 1.5c to 3c)") {
    std::mt19937 rng(51);
    for (int k = 0; k < 40; ++k) {
      std::array<Real3, 4> const e = RandomEdgePair(rng);
      real const threshold =
          Uniform(rng, 1.5, 3) * EdgeEdgeCrossSquaredNorm(e[0], e[1], e[2], e[3]);
      RequireDerivatives<12>(
          [threshold](Vec<12> const& y) {
            return EdgeEdgeMollifier(Node(y, 0), Node(y, 1), Node(y, 2), Node(y, 3), threshold);
          },
          [threshold](Vec<12> const& y) {
            return EdgeEdgeMollifierGradient(Node(y, 0), Node(y, 1), Node(y, 2), Node(y, 3),
                                             threshold);
          },
          [threshold](Vec<12> const& y) {
            return EdgeEdgeMollifierHessian(Node(y, 0), Node(y, 1), Node(y, 2), Node(y, 3),
                                            threshold);
          },
          Pack(e[0], e[1], e[2], e[3]));
    }
  }
  SECTION("mollified squared distance m·d² (product rule) against central differences") {
    std::mt19937 rng(52);
    for (int k = 0; k < 20; ++k) {
      std::array<Real3, 4> const e = RandomEdgePair(rng);
      real const threshold = 2 * EdgeEdgeCrossSquaredNorm(e[0], e[1], e[2], e[3]);
      EdgeEdgeType const type = EdgeEdgeDistanceType(e[0], e[1], e[2], e[3]);
      auto product = [threshold, type](Vec<12> const& y) {
        Real3 const a0 = Node(y, 0), a1 = Node(y, 1), b0 = Node(y, 2), b1 = Node(y, 3);
        return Multiply(EdgeEdgeMollifierDerivatives(a0, a1, b0, b1, threshold),
                        EdgeEdgeDistance2Derivatives(a0, a1, b0, b1, type));
      };
      RequireDerivatives<12>([&](Vec<12> const& y) { return product(y).value; },
                             [&](Vec<12> const& y) { return product(y).gradient; },
                             [&](Vec<12> const& y) { return product(y).hessian; },
                             Pack(e[0], e[1], e[2], e[3]));
    }
  }
}

// ---------------------------------------------------------------- (f)

TEST_CASE(
    "Tangent frames: orthonormal, orthogonal to the normal, weights give the closest-point vector",
    "[contact][distance]") {
  // For every type: TᵀT = I; Γx = (first closest point) − (second) has
  // squared norm d² (the type's distance) and Tᵀ Γx = 0; Γ applied to a rigid
  // translation of the pair is zero. All to round-off of O(1) numbers (1e-12).
  static constexpr real kTol = 1e-12;
  auto requireFrame = [](auto const& frame, auto const& x, real distance2) {
    REQUIRE(MaxAbs(frame.basis.transpose() * frame.basis - Matrix2::Identity()) <= kTol);
    Real3 const gap = frame.weights * x;
    REQUIRE(Near(gap.squaredNorm(), distance2, kTol));
    REQUIRE(MaxAbs(frame.basis.transpose() * gap) <= kTol * std::max(gap.norm(), real(1)));
    REQUIRE(gap.norm() > 1e-3);  // the previous check is not about a zero vector
    Real3 const shift(0.3, -0.7, 1.1);
    auto translated = x;
    for (int i = 0; i < x.size() / 3; ++i) translated.template segment<3>(3 * i) = shift;
    REQUIRE(MaxAbs(frame.weights * translated) <= kTol);
  };
  std::mt19937 rng(61);
  std::map<int, int> seenPt, seenEe, seenPe;
  for (int k = 0; k < 600; ++k) {
    CAPTURE(k);
    std::array<Real3, 3> const t = RandomTriangle(rng);
    Real3 const p = RandomPointNear(rng, t);
    PointTriangleType const ptType = PointTriangleDistanceType(p, t[0], t[1], t[2]);
    ++seenPt[ToInt(ptType)];
    requireFrame(PointTriangleTangentFrame(p, t[0], t[1], t[2], ptType), Pack(p, t[0], t[1], t[2]),
                 PointTriangleDistance2(p, t[0], t[1], t[2], ptType));
    if (ptType == PointTriangleType::P_T) {  // the basis spans the triangle's plane, first column
                                             // along t1 − t0
      TangentBasis const basis = PointTriangleTangentBasis(t[0], t[1], t[2]);
      REQUIRE(MaxAbs(basis.transpose() * (t[1] - t[0]).cross(t[2] - t[0])) <= kTol);
      REQUIRE(Near(basis.col(0).dot((t[1] - t[0]).normalized()), 1, kTol));
    }

    std::array<Real3, 4> const e = RandomEdgePair(rng);
    EdgeEdgeType const eeType = EdgeEdgeDistanceType(e[0], e[1], e[2], e[3]);
    ++seenEe[ToInt(eeType)];
    requireFrame(EdgeEdgeTangentFrame(e[0], e[1], e[2], e[3], eeType), Pack(e[0], e[1], e[2], e[3]),
                 EdgeEdgeDistance2(e[0], e[1], e[2], e[3], eeType));
    if (eeType == EdgeEdgeType::EA_EB) {  // spanned by edge a and normal × edge a
      TangentBasis const basis = EdgeEdgeTangentBasis(e[0], e[1], e[2], e[3]);
      REQUIRE(Near(basis.col(0).dot((e[1] - e[0]).normalized()), 1, kTol));
      REQUIRE(MaxAbs(basis.transpose() * (e[1] - e[0]).cross(e[3] - e[2])) <= kTol);
    }

    PointEdgeType const peType = PointEdgeDistanceType(t[0], t[1], t[2]);
    ++seenPe[ToInt(peType)];
    Vec<9> xPe;
    xPe << t[0], t[1], t[2];
    requireFrame(PointEdgeTangentFrame(t[0], t[1], t[2], peType), xPe,
                 PointEdgeDistance2(t[0], t[1], t[2], peType));
  }
  REQUIRE(seenPt.size() == 7);
  REQUIRE(seenEe.size() == 9);
  REQUIRE(seenPe.size() == 3);
  SECTION("coincident points and a point on the edge's line still get an orthonormal basis") {
    Real3 const a(0.1, 0.2, 0.3);
    for (TangentBasis const& basis :
         {PointPointTangentBasis(a, a),
          PointEdgeTangentBasis(Real3(2, 0, 0), Real3(0, 0, 0), Real3(1, 0, 0)),
          PointEdgeTangentBasis(a, a, a), EdgeEdgeTangentBasis(a, a, a, a)}) {
      REQUIRE(basis.allFinite());
      REQUIRE(MaxAbs(basis.transpose() * basis - Matrix2::Identity()) <= kTol);
    }
    // on the line the first column is still the edge direction
    REQUIRE(
        Near(PointEdgeTangentBasis(Real3(2, 0, 0), Real3(0, 0, 0), Real3(1, 0, 0))(0, 0), 1, kTol));
  }
}

// Continuous collision detection (contact/ccd.h): analytic impacts whose
// time is known in closed form; on 12,000 random trajectories the guarantee,
// judged by the distance sampled densely, where the answer must fall
// (between two crossing times found by a certified search) and how it
// compares with the first impact; starting in contact; the iteration cap.
//
// The guarantee checked everywhere (ccd.h): with g(t) = d(t) − ξ and
// g* = (1 − s)·g(0), g(t) ≥ g* on [0, t*]. Where the gap falls linearly at
// speed v, additive CCD stops once g − g* ≤ η·s·g(0) (η = kCcdStopFraction),
// so t* lies in [(1 − η)·t_s, t_s] with t_s = s·g(0)/v the time the gap
// reaches g*; the analytic tests assert exactly that window.
#include "test_support.h"

#include <superdex/contact/ccd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>

using namespace superdex;
using namespace superdex::test;
using namespace superdex::contact;

namespace {

constexpr real kS = kCcdRescale;
constexpr real kEta = kCcdStopFraction;

// Times computed from exact data through a few divisions and square roots:
// a few ulps. 1e-12 relative leaves four decades of margin; a wrong target
// (say g* = s·g(0) instead of (1 − s)·g(0)) errs by 10 % or more.
constexpr real kTimeTol = 1e-12;

// ---- distances of the test's own, by a different route than ccd.cc:
// every stationary point of the squared distance over the closed primitive
// (its interior through the Gram system, each edge, each vertex) ----

real PointSegmentDistance(Real3 const& p, Real3 const& a, Real3 const& b) {
  real best = std::min((p - a).norm(), (p - b).norm());
  Real3 const e = b - a;
  real const ee = e.squaredNorm();
  if (ee > 0) {
    real const u = (p - a).dot(e) / ee;
    if (u > 0 && u < 1) best = std::min(best, (a + u * e - p).norm());
  }
  return best;
}

real PointTriangleDistance(Real3 const& p, Real3 const& a, Real3 const& b, Real3 const& c) {
  real best = std::min({PointSegmentDistance(p, a, b), PointSegmentDistance(p, b, c),
                        PointSegmentDistance(p, c, a)});
  Real3 const e1 = b - a, e2 = c - a, w = p - a;
  Eigen::Matrix2d gram;
  gram << e1.dot(e1), e1.dot(e2), e1.dot(e2), e2.dot(e2);
  if (gram.determinant() > 1e-14 * gram(0, 0) * gram(1, 1)) {
    Eigen::Vector2d const uv = gram.ldlt().solve(Eigen::Vector2d(e1.dot(w), e2.dot(w)));
    if (uv[0] >= 0 && uv[1] >= 0 && uv[0] + uv[1] <= 1)
      best = std::min(best, (a + uv[0] * e1 + uv[1] * e2 - p).norm());
  }
  return best;
}

real SegmentSegmentDistance(Real3 const& a0, Real3 const& a1, Real3 const& b0, Real3 const& b1) {
  real best = std::min({PointSegmentDistance(a0, b0, b1), PointSegmentDistance(a1, b0, b1),
                        PointSegmentDistance(b0, a0, a1), PointSegmentDistance(b1, a0, a1)});
  Real3 const u = a1 - a0, v = b1 - b0, w = b0 - a0;
  Eigen::Matrix2d gram;
  gram << u.dot(u), -u.dot(v), -u.dot(v), v.dot(v);
  if (gram.determinant() > 1e-14 * gram(0, 0) * gram(1, 1)) {
    Eigen::Vector2d const st = gram.ldlt().solve(Eigen::Vector2d(u.dot(w), -v.dot(w)));
    if (st[0] > 0 && st[0] < 1 && st[1] > 0 && st[1] < 1)
      best = std::min(best, (a0 + st[0] * u - b0 - st[1] * v).norm());
  }
  return best;
}

// ---- a pair of primitives on linear trajectories ----

enum class Kind { PointTriangle, EdgeEdge, PointEdge, PointPoint };

char const* Name(Kind kind) {
  switch (kind) {
    case Kind::PointTriangle: return "point-triangle";
    case Kind::EdgeEdge: return "edge-edge";
    case Kind::PointEdge: return "point-edge";
    case Kind::PointPoint: return "point-point";
  }
  return "?";
}

int NumVertices(Kind kind) {
  switch (kind) {
    case Kind::PointTriangle:
    case Kind::EdgeEdge: return 4;
    case Kind::PointEdge: return 3;
    case Kind::PointPoint: return 2;
  }
  return 0;
}

struct Pair {
  Kind kind = Kind::PointPoint;
  std::array<Real3, 4> x{};   ///< start positions (the first NumVertices used)
  std::array<Real3, 4> dx{};  ///< displacements
  real thickness = 0;
};

real Distance(Pair const& pair, real t) {
  std::array<Real3, 4> p;
  for (int i = 0; i < 4; ++i) p[i] = pair.x[i] + t * pair.dx[i];
  switch (pair.kind) {
    case Kind::PointTriangle: return PointTriangleDistance(p[0], p[1], p[2], p[3]);
    case Kind::EdgeEdge: return SegmentSegmentDistance(p[0], p[1], p[2], p[3]);
    case Kind::PointEdge: return PointSegmentDistance(p[0], p[1], p[2]);
    case Kind::PointPoint: return (p[0] - p[1]).norm();
  }
  return 0;
}

real Gap(Pair const& pair, real t) { return Distance(pair, t) - pair.thickness; }

real Ccd(Pair const& pair, real tMax, real rescale = kS, int maxIterations = kCcdMaxIterations) {
  auto const& x = pair.x;
  auto const& d = pair.dx;
  real const xi = pair.thickness;
  switch (pair.kind) {
    case Kind::PointTriangle:
      return PointTriangleCcd(x[0], x[1], x[2], x[3], d[0], d[1], d[2], d[3], xi, tMax, rescale,
                              maxIterations);
    case Kind::EdgeEdge:
      return EdgeEdgeCcd(x[0], x[1], x[2], x[3], d[0], d[1], d[2], d[3], xi, tMax, rescale,
                         maxIterations);
    case Kind::PointEdge:
      return PointEdgeCcd(x[0], x[1], x[2], d[0], d[1], d[2], xi, tMax, rescale, maxIterations);
    case Kind::PointPoint:
      return PointPointCcd(x[0], x[1], d[0], d[1], xi, tMax, rescale, maxIterations);
  }
  return -1;
}

// A bound on |ḋ|: every point of either primitive moves at most the largest
// vertex displacement, so their distance changes at most twice that per
// unit time (looser than additive CCD's bound, and independent of it).
real SpeedBound(Pair const& pair) {
  real fastest = 0;
  for (int i = 0; i < NumVertices(pair.kind); ++i) fastest = std::max(fastest, pair.dx[i].norm());
  return 2 * fastest;
}

// The analytic cases: the gap falls linearly at speed v from g(0), so the
// answer must lie in [(1 − η)·t_s, t_s], t_s = s·g(0)/v.
void RequireLinearImpactWindow(Pair const& pair, real startGap, real speed) {
  real const ts = kS * startGap / speed;
  real const t = Ccd(pair, 1);
  CAPTURE(Name(pair.kind), startGap, speed, ts, t);
  REQUIRE(Near(Gap(pair, 0), startGap, kTimeTol));
  REQUIRE(t <= ts * (1 + kTimeTol));
  REQUIRE(t >= (1 - kEta) * ts * (1 - kTimeTol));
  // and the gap there is what the linear fall says: at least g*
  REQUIRE(Gap(pair, t) >= (1 - kS) * startGap * (1 - kTimeTol));
}

Pair MakePair(Kind kind, std::initializer_list<Real3> x, std::initializer_list<Real3> dx,
              real thickness) {
  Pair pair;
  pair.kind = kind;
  std::copy(x.begin(), x.end(), pair.x.begin());
  std::copy(dx.begin(), dx.end(), pair.dx.begin());
  pair.thickness = thickness;
  return pair;
}

Real3 RandomIn(std::mt19937& rng, real half) {
  std::uniform_real_distribution<real> u(-half, half);
  return Real3(u(rng), u(rng), u(rng));
}

// ---- random trajectories ----

enum class Family {
  Scattered,  ///< vertices anywhere in [−1, 1]³, displacements anywhere in [−1.5, 1.5]³
  Aimed,      ///< the primitives 1.5 apart, translated towards each other, deforming a little
  Tight,      ///< Aimed with the positions shrunk 20×: gaps far below the motion
};

char const* Name(Family family) {
  switch (family) {
    case Family::Scattered: return "scattered";
    case Family::Aimed: return "aimed";
    case Family::Tight: return "tight";
  }
  return "?";
}

Pair RandomPair(Kind kind, Family family, std::mt19937& rng) {
  std::uniform_real_distribution<real> unit(0, 1);
  Pair pair;
  pair.kind = kind;
  int const numVertices = NumVertices(kind);
  int const numA = kind == Kind::EdgeEdge ? 2 : 1;
  if (family == Family::Scattered) {
    for (int i = 0; i < numVertices; ++i) {
      pair.x[i] = RandomIn(rng, 1);
      pair.dx[i] = RandomIn(rng, 1.5);
    }
    pair.thickness = 0.3 * unit(rng);
    return pair;
  }
  // B's vertices around a centre 1.5 away in a random direction; B moves
  // towards A by 0.6 to 2 times that, and every vertex deforms by up to 0.3
  real const scale = family == Family::Tight ? 0.05 : 1;
  Real3 const center = 1.5 * RandomIn(rng, 1).normalized();
  Real3 const approach = -(0.6 + 1.4 * unit(rng)) * center;
  for (int i = 0; i < numVertices; ++i) {
    bool const onB = i >= numA;
    pair.x[i] = scale * ((onB ? center : Real3::Zero()) + RandomIn(rng, 0.5));
    pair.dx[i] = (onB ? approach : Real3::Zero()) + RandomIn(rng, 0.3);
  }
  pair.thickness = 0.3 * scale * unit(rng);
  return pair;
}

// The first time the gap falls to `level` on [0, tMax], found on a grid
// and refined where the speed bound V cannot rule a crossing out: between
// two times h apart where the gap is above the level by a and b, it stays
// above unless a + b ≤ V·h (it is at least max(a − V·τ, b − V·(h − τ))).
// Intervals that cannot be ruled out down to 1e-12 are unresolved: the gap
// may touch the level there (a tangency). The answer is `certified` when no
// interval before the crossing found is unresolved, except one within 1e-9
// of it; then the true first crossing is within 1e-9 of `time`, or, when
// none was found, there is none on [0, tMax].
struct Crossing {
  bool found = false;
  bool certified = false;
  real time = 0;
};

class CrossingFinder {
 public:
  CrossingFinder(Pair const& pair, real level)
      : pair_(pair), level_(level), speed_(SpeedBound(pair)) {}

  Crossing Find(real tMax) {
    constexpr int kGrid = 256;
    real const h = tMax / kGrid;
    real previous = Above(0);
    Crossing result;
    if (previous <= 0) return {true, true, 0};
    for (int k = 1; k <= kGrid && !result.found; ++k) {
      real const above = Above(k * h);
      if (real const time = First((k - 1) * h, k * h, previous, above); time >= 0) {
        result.found = true;
        result.time = time;
      }
      previous = above;
    }
    real const unresolvedUpTo = result.found ? result.time - 1e-9 : tMax;
    result.certified = !overBudget_ && !(firstUnresolved_ < unresolvedUpTo);
    return result;
  }

 private:
  real Above(real t) const { return Gap(pair_, t) - level_; }

  // the first crossing in [lo, hi] (to within 1e-12) given the gap above
  // the level by a > 0 at lo and by b at hi, or −1 if none was found
  real First(real lo, real hi, real a, real b) {
    if (b > 0 && a + b > speed_ * (hi - lo)) return -1;  // ruled out
    if (hi - lo <= 1e-12 || ++evaluations_ > kBudget) {
      if (b <= 0) return hi;
      firstUnresolved_ = std::min(firstUnresolved_, lo);
      overBudget_ = overBudget_ || evaluations_ > kBudget;
      return -1;
    }
    real const mid = (lo + hi) / 2;
    real const aboveMid = Above(mid);
    if (real const left = First(lo, mid, a, aboveMid); left >= 0) return left;
    if (aboveMid <= 0) return mid;
    return First(mid, hi, aboveMid, b);
  }

  static constexpr int kBudget = 100000;
  Pair const& pair_;
  real level_;
  real speed_;
  real firstUnresolved_ = std::numeric_limits<real>::infinity();
  bool overBudget_ = false;
  int evaluations_ = 0;
};

Crossing FirstCrossing(Pair const& pair, real level, real tMax) {
  return CrossingFinder(pair, level).Find(tMax);
}

}  // namespace

TEST_CASE("The test's own distances match dense sampling of the primitives", "[contact][ccd]") {
  // the helpers judge every other test here, so they are checked first:
  // never above the sampled minimum (they are minima) and within the
  // sampling's resolution of it (they are attained)
  std::mt19937 rng(11);
  constexpr int kSteps = 200;
  for (int trial = 0; trial < 60; ++trial) {
    std::array<Real3, 4> v;
    for (Real3& p : v) p = RandomIn(rng, 1);
    CAPTURE(trial);
    real const edgeMax = std::max({(v[1] - v[0]).norm(), (v[2] - v[1]).norm(), (v[3] - v[2]).norm(),
                                   (v[3] - v[1]).norm(), (v[2] - v[0]).norm()});
    // the sampling's resolution: a parameter step of 1/kSteps moves a point
    // by at most edgeMax/kSteps per parameter, and two parameters move
    real const resolution = 2 * edgeMax / kSteps;

    real sampledTriangle = std::numeric_limits<real>::infinity();
    real sampledSegments = std::numeric_limits<real>::infinity();
    for (int i = 0; i <= kSteps; ++i) {
      for (int j = 0; j <= kSteps; ++j) {
        real const a = real(i) / kSteps, b = real(j) / kSteps;
        sampledSegments = std::min(
            sampledSegments, (v[0] + a * (v[1] - v[0]) - v[2] - b * (v[3] - v[2])).norm());
        if (i + j <= kSteps) {
          Real3 const onTriangle = v[1] + a * (v[2] - v[1]) + b * (v[3] - v[1]);
          sampledTriangle = std::min(sampledTriangle, (onTriangle - v[0]).norm());
        }
      }
    }
    real const triangle = PointTriangleDistance(v[0], v[1], v[2], v[3]);
    real const segments = SegmentSegmentDistance(v[0], v[1], v[2], v[3]);
    CAPTURE(triangle, sampledTriangle, segments, sampledSegments);
    REQUIRE(triangle <= sampledTriangle + 1e-12);
    REQUIRE(sampledTriangle <= triangle + resolution);
    REQUIRE(segments <= sampledSegments + 1e-12);
    REQUIRE(sampledSegments <= segments + resolution);
  }
  // parallel and collinear segments, and a point over a triangle's interior
  REQUIRE(Near(SegmentSegmentDistance({0, 0, 0}, {1, 0, 0}, {0.5, 0, 2}, {3, 0, 2}), 2, 1e-15));
  REQUIRE(Near(SegmentSegmentDistance({0, 0, 0}, {1, 0, 0}, {1.5, 0, 0}, {3, 0, 0}), 0.5, 1e-15));
  REQUIRE(
      Near(PointTriangleDistance({0.2, 0.2, 0.7}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}), 0.7, 1e-15));
}

TEST_CASE("A point falling onto a triangle's interior stops within the rescaled gap of impact",
          "[contact][ccd]") {
  real const thickness = 0.01;
  // straight down at speed 2 from height 1: t_impact = 0.495
  RequireLinearImpactWindow(
      MakePair(Kind::PointTriangle, {{0.2, 0.2, 1}, {-1, -1, 0}, {2, -1, 0}, {-1, 2, 0}},
               {{0, 0, -2}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}}, thickness),
      1 - thickness, 2);
  // the same fall while the triangle slides in its plane: the bound L is
  // larger than the closing speed, so several advances are needed
  RequireLinearImpactWindow(
      MakePair(Kind::PointTriangle, {{0.2, 0.2, 1}, {-3, -3, 0}, {4, -3, 0}, {-3, 4, 0}},
               {{0, 0, -2}, {1.5, 0.5, 0}, {1.5, 0.5, 0}, {1.5, 0.5, 0}}, thickness),
      1 - thickness, 2);
  // the triangle rising to meet the point
  RequireLinearImpactWindow(
      MakePair(Kind::PointTriangle, {{0.2, 0.2, 1}, {-1, -1, 0}, {2, -1, 0}, {-1, 2, 0}},
               {{0, 0, 0}, {0, 0, 3}, {0, 0, 3}, {0, 0, 3}}, thickness),
      1 - thickness, 3);
}

TEST_CASE("A point hitting a triangle's edge or vertex stops within the rescaled gap of impact",
          "[contact][ccd]") {
  real const thickness = 0.02;
  // the triangle (0,0,0), (1,0,0), (0.5,1,0)
  Real3 const a(0, 0, 0), b(1, 0, 0), c(0.5, 1, 0);
  Real3 const still = Real3::Zero();
  SECTION("edge, in the triangle's plane") {
    // from (0.5, -1, 0) straight at the edge ab at speed 2
    RequireLinearImpactWindow(
        MakePair(Kind::PointTriangle, {{0.5, -1, 0}, a, b, c}, {{0, 2, 0}, still, still, still},
                 thickness),
        1 - thickness, 2);
  }
  SECTION("edge, from outside the plane") {
    // along the edge's outward bisector (0, -1, 1)/√2 at speed 2
    Real3 const from = Real3(0.5, 0, 0) + Real3(0, -1, 1);
    Real3 const dp = -2 * Real3(0, -1, 1).normalized();
    RequireLinearImpactWindow(
        MakePair(Kind::PointTriangle, {from, a, b, c}, {dp, still, still, still}, thickness),
        std::sqrt(2.0) - thickness, 2);
  }
  SECTION("vertex") {
    // from the vertex a's region, (-1, -1, 0.5) away, straight at it
    Real3 const from(-1, -1, 0.5);
    Real3 const dp = -1.5 * from.normalized();
    RequireLinearImpactWindow(
        MakePair(Kind::PointTriangle, {from, a, b, c}, {dp, still, still, still}, thickness),
        from.norm() - thickness, 1.5);
  }
}

TEST_CASE("Crossing and parallel edges stop within the rescaled gap of impact", "[contact][ccd]") {
  real const thickness = 0.05;
  Real3 const still = Real3::Zero();
  SECTION("crossing") {
    // an x edge above a y edge, falling at speed 2
    RequireLinearImpactWindow(
        MakePair(Kind::EdgeEdge, {{-1, 0.3, 1}, {1, 0.3, 1}, {0.2, -1, 0}, {0.2, 1, 0}},
                 {{0, 0, -2}, {0, 0, -2}, still, still}, thickness),
        1 - thickness, 2);
  }
  SECTION("parallel, overlapping, moving into each other") {
    // both move, 1 and 0.5 towards each other
    RequireLinearImpactWindow(
        MakePair(Kind::EdgeEdge, {{0, 0, 1}, {1, 0, 1}, {0.5, 0, 0}, {1.5, 0, 0}},
                 {{0, 0, -1}, {0, 0, -1}, {0, 0, 0.5}, {0, 0, 0.5}}, thickness),
        1 - thickness, 1.5);
  }
  SECTION("collinear, end to end") {
    RequireLinearImpactWindow(
        MakePair(Kind::EdgeEdge, {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}},
                 {{2, 0, 0}, {2, 0, 0}, still, still}, thickness),
        1 - thickness, 2);
  }
  SECTION("parallel, sliding along each other while closing") {
    RequireLinearImpactWindow(
        MakePair(Kind::EdgeEdge, {{0, 0, 0.6}, {1, 0, 0.6}, {-0.5, 0, 0}, {2, 0, 0}},
                 {{0.8, 0, -1}, {0.8, 0, -1}, still, still}, thickness),
        0.6 - thickness, 1);
  }
}

TEST_CASE("Rods with radii: point-point and point-edge stop within the rescaled gap of impact",
          "[contact][ccd]") {
  Real3 const still = Real3::Zero();
  // radii 0.1 and 0.2: thickness 0.3; head on, 1 apart, closing at speed 1
  real const radii = 0.1 + 0.2;
  RequireLinearImpactWindow(MakePair(Kind::PointPoint, {{0, 0, 0}, {1, 0, 0}},
                                     {{0.5, 0, 0}, {-0.5, 0, 0}}, radii),
                            1 - radii, 1);
  // a rod node falling onto the middle of a rod segment, and onto its end
  RequireLinearImpactWindow(MakePair(Kind::PointEdge, {{0.4, 0, 1}, {-1, 0, 0}, {1, 0, 0}},
                                     {{0, 0, -2}, still, still}, radii),
                            1 - radii, 2);
  RequireLinearImpactWindow(MakePair(Kind::PointEdge, {{2, 0, 0}, {-1, 0, 0}, {1, 0, 0}},
                                     {{-4, 0, 0}, still, still}, radii),
                            1 - radii, 4);
}

TEST_CASE("The plane and the sphere return exactly the time the gap closes by the rescaling",
          "[contact][ccd]") {
  SECTION("point against a static and a moving plane") {
    // z ≥ 0.5 via the non-unit normal (0, 0, 2), offset 1; radius 0.1,
    // from z = 2 at speed 3: g(0) = 1.4, t = 0.9·1.4/3
    real const t = PointPlaneCcd({0.3, -7, 2}, {5, 1, -3}, 0.1, {0, 0, 2}, 1, 0, 1);
    REQUIRE(Near(t, kS * 1.4 / 3, kTimeTol));
    // the plane rising by 0.6 (offset 1.2 for the normal's length 2): closing speed 3.6
    real const tMoving = PointPlaneCcd({0.3, -7, 2}, {5, 1, -3}, 0.1, {0, 0, 2}, 1, 1.2, 1);
    REQUIRE(Near(tMoving, kS * 1.4 / 3.6, kTimeTol));
    // too slow to reach the target within tMax, moving away, sliding along
    REQUIRE(PointPlaneCcd({0, 0, 2}, {0, 0, -1}, 0.1, {0, 0, 2}, 1, 0, 1) == 1);
    REQUIRE(PointPlaneCcd({0, 0, 2}, {0, 0, -1}, 0.1, {0, 0, 2}, 1, 0, 0.5) == 0.5);
    REQUIRE(PointPlaneCcd({0, 0, 2}, {0, 0, 1}, 0.1, {0, 0, 2}, 1, 0, 1) == 1);
    REQUIRE(PointPlaneCcd({0, 0, 2}, {4, 0, 0}, 0.1, {0, 0, 2}, 1, 0, 1) == 1);
    // the radius reaching the plane at the start, or beyond it
    REQUIRE(PointPlaneCcd({0, 0, 0.6}, {0, 0, -1}, 0.1, {0, 0, 2}, 1, 0, 1) == 0);
    REQUIRE(PointPlaneCcd({0, 0, 0.55}, {0, 0, 1}, 0.1, {0, 0, 2}, 1, 0, 1) == 0);
    // another rescaling keeps its share: s = 0.5 stops halfway
    REQUIRE(Near(PointPlaneCcd({0.3, -7, 2}, {5, 1, -3}, 0.1, {0, 0, 2}, 1, 0, 1, 0.5),
                 0.5 * 1.4 / 3, kTimeTol));
  }
  SECTION("point against a static and a moving sphere") {
    Real3 const center(1, 2, 3);
    real const radius = 0.2, sphereRadius = 0.5;
    // head on from 3 away at speed 4: g(0) = 2.3, t = 0.9·2.3/4
    Real3 const from = center + Real3(0, 3, 0);
    REQUIRE(Near(PointSphereCcd(from, {0, -4, 0}, radius, center, {0, 0, 0}, sphereRadius, 1),
                 kS * 2.3 / 4, kTimeTol));
    // the sphere coming too, at speed 1
    REQUIRE(Near(PointSphereCcd(from, {0, -4, 0}, radius, center, {0, 1, 0}, sphereRadius, 1),
                 kS * 2.3 / 5, kTimeTol));
    // oblique: the gap at t is exactly the target, and above it before
    Real3 const dp(0.3, -3.5, 0.4);
    real const startGap = 3 - radius - sphereRadius;
    real const target = (1 - kS) * startGap;
    real const t = PointSphereCcd(from, dp, radius, center, {0, 0, 0}, sphereRadius, 1);
    auto const gapAt = [&](real s) {
      return (from + s * dp - center).norm() - radius - sphereRadius;
    };
    CAPTURE(t, gapAt(t), target);
    REQUIRE(t > 0);
    REQUIRE(t < 1);
    REQUIRE(std::abs(gapAt(t) - target) <= 1e-12);
    for (int k = 0; k < 1000; ++k) REQUIRE(gapAt(t * k / 1000) > target);
    // passing by outside the target: tMax; moving away: tMax; inside: 0
    REQUIRE(PointSphereCcd(center + Real3(2, 3, 0), {0, -6, 0}, radius, center, {0, 0, 0},
                           sphereRadius, 1) == 1);
    REQUIRE(PointSphereCcd(from, {0, 4, 0}, radius, center, {0, 0, 0}, sphereRadius, 0.7) == 0.7);
    // (radii 0.25 + 0.5: the start distance 0.75 is exact)
    REQUIRE(PointSphereCcd(center + Real3(0, 0.75, 0), {0, -1, 0}, 0.25, center, {0, 0, 0},
                           sphereRadius, 1) == 0);
    REQUIRE(PointSphereCcd(center, {0, 1, 0}, radius, center, {0, 0, 0}, sphereRadius, 1) == 0);
  }
}

TEST_CASE("Pairs starting at or below the thickness return 0", "[contact][ccd]") {
  Real3 const still = Real3::Zero();
  Real3 const away(0, 0, 1);
  // each pair's start distance is exactly 0.5 and the motion separates them
  Pair const pairs[] = {
      MakePair(Kind::PointTriangle, {{0.2, 0.2, 0.5}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
               {away, still, still, still}, 0),
      MakePair(Kind::EdgeEdge, {{-1, 0, 0.5}, {1, 0, 0.5}, {0, -1, 0}, {0, 1, 0}},
               {away, away, still, still}, 0),
      MakePair(Kind::PointEdge, {{0, 0, 0.5}, {-1, 0, 0}, {1, 0, 0}}, {away, still, still}, 0),
      MakePair(Kind::PointPoint, {{0, 0, 0.5}, {0, 0, 0}}, {away, still}, 0),
  };
  for (Pair pair : pairs) {
    CAPTURE(Name(pair.kind));
    REQUIRE(Distance(pair, 0) == 0.5);
    pair.thickness = 0.4;
    REQUIRE(Ccd(pair, 1) == 1);  // apart at the start: the separating motion is free
    pair.thickness = 0.5;
    REQUIRE(Ccd(pair, 1) == 0);
    pair.thickness = 0.7;
    REQUIRE(Ccd(pair, 1) == 0);
  }
}

TEST_CASE("Pairs that never come within range return tMax", "[contact][ccd]") {
  Real3 const still = Real3::Zero();
  // separating, sliding in parallel far apart, and no relative motion at all
  Pair const pairs[] = {
      MakePair(Kind::PointTriangle, {{0.2, 0.2, 0.5}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
               {{0, 0, 1}, still, still, still}, 0.1),
      MakePair(Kind::EdgeEdge, {{-1, 0, 2}, {1, 0, 2}, {-1, 0, 0}, {1, 0, 0}},
               {{3, 1, 0}, {3, 1, 0}, still, still}, 0.1),
      MakePair(Kind::PointEdge, {{0, 0, 1}, {-1, 0, 0}, {1, 0, 0}},
               {{5, 5, 5}, {5, 5, 5}, {5, 5, 5}}, 0.1),
      MakePair(Kind::PointPoint, {{0, 0, 1}, {0, 0, 0}}, {{0.3, 0, 0}, {-0.3, 0, 0}}, 0.1),
  };
  for (Pair const& pair : pairs) {
    CAPTURE(Name(pair.kind));
    REQUIRE(Ccd(pair, 1) == 1);
    REQUIRE(Ccd(pair, 0.25) == 0.25);
    REQUIRE(Ccd(pair, 0) == 0);
  }
}

TEST_CASE("The iteration cap returns the last advanced time, which is safe", "[contact][ccd]") {
  // two points closing obliquely: the gap falls slower than the bound L
  // allows, so additive CCD advances in several steps; both also share a
  // translation, which the mean's removal takes out of L
  Real3 const common(3, -1, 2);
  Pair const pair = MakePair(Kind::PointPoint, {{0, 0, 0}, {1, 0, 0}},
                             {common, common + Real3(-1.2, 2, 0)}, 0.1);
  real const lipschitz = Real3(-1.2, 2, 0).norm();  // mean removed: each point half of it
  real const startGap = Gap(pair, 0);
  real const target = (1 - kS) * startGap;
  // one evaluation: the first advance, s·g(0)/L; two: one more from there
  real const t1 = kS * startGap / lipschitz;
  real const t2 = t1 + (Gap(pair, t1) - target) / lipschitz;
  real const capped1 = Ccd(pair, 1, kS, 1);
  real const capped2 = Ccd(pair, 1, kS, 2);
  real const free = Ccd(pair, 1);
  CAPTURE(t1, t2, capped1, capped2, free);
  REQUIRE(Near(capped1, t1, kTimeTol));
  REQUIRE(Near(capped2, t2, kTimeTol));
  REQUIRE(capped2 > capped1 * (1 + 1e-3));
  REQUIRE(free > capped2 * (1 + 1e-3));
  // more evaluations than the stop needs change nothing
  REQUIRE(Ccd(pair, 1, kS, 100) == free);
  // each capped answer keeps the gap above the target
  for (real t : {capped1, capped2, free}) {
    for (int k = 0; k <= 1000; ++k) REQUIRE(Gap(pair, t * k / 1000) >= target * (1 - kTimeTol));
  }
  // no evaluation at all: nothing is certified, 0
  REQUIRE(Ccd(pair, 1, kS, 0) == 0);
}

TEST_CASE("Random trajectories: t* keeps the target gap and stops where additive CCD must",
          "[long][contact][ccd]") {
  // Every trial checks, with the start gap g(0) > 0:
  //  - safety: g ≥ g* at 1000 times evenly over [0, t*] and at t*;
  //  - the window: t* ≥ t_η, the first time g falls to g* + η·s·g(0) (the
  //    iteration cannot stop while every advanced time is above that level,
  //    and it cannot pass it without stopping unless the gap rises again),
  //    and t* ≤ t_s, the first time g falls to g*; t* = tMax when g stays
  //    above g* + η·s·g(0) on [0, tMax]. Both crossings come from the
  //    certified search above; the levels are moved by δ = 1e-10·g(0)
  //    outwards, for round-off in the two distance routines;
  //  - against the first impact (g = 0) where certified: t*/t_impact. No
  //    ratio holds for every trajectory (a gap can fall quickly to the
  //    target and then creep to contact: t* stops early by design), so at
  //    most 1 % of the impacts may have t* < 0.5·t_impact, and the mean
  //    ratio must be at least 0.75.
  Kind const kind =
      GENERATE(Kind::PointTriangle, Kind::EdgeEdge, Kind::PointEdge, Kind::PointPoint);
  Family const family = GENERATE(Family::Scattered, Family::Aimed, Family::Tight);
  CAPTURE(Name(kind), Name(family));
  std::mt19937 rng(1000 + 10 * static_cast<int>(kind) + static_cast<int>(family));

  constexpr int kTrials = 1000;
  constexpr int kSafetySamples = 1000;  // on [0, t*]
  constexpr real kCrossingTol = 1e-9;
  real const tMax = 1;
  int startInside = 0, windowChecks = 0, clearOfRange = 0, impacts = 0, belowHalf = 0;
  real worstRatio = std::numeric_limits<real>::infinity(), ratioSum = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    Pair const pair = RandomPair(kind, family, rng);
    CAPTURE(trial);
    real const t = Ccd(pair, tMax);
    REQUIRE(t >= 0);
    REQUIRE(t <= tMax);
    real const startGap = Gap(pair, 0);
    if (startGap <= 0) {
      ++startInside;
      REQUIRE(t == 0);
      continue;
    }
    real const target = (1 - kS) * startGap;
    real const stopLevel = target + kEta * kS * startGap;
    real const delta = 1e-10 * startGap;

    // safety
    real worstGap = Gap(pair, t);
    for (int k = 0; k < kSafetySamples; ++k)
      worstGap = std::min(worstGap, Gap(pair, t * k / kSafetySamples));
    CAPTURE(t, startGap, target, worstGap);
    REQUIRE(worstGap >= target - 1e-12);
    REQUIRE(worstGap > 0);

    // the window
    Crossing const stop = FirstCrossing(pair, stopLevel + delta, tMax);
    Crossing const reach = FirstCrossing(pair, target - delta, tMax);
    CAPTURE(stop.found, stop.certified, stop.time, reach.found, reach.certified, reach.time);
    if (stop.certified) {
      if (stop.found) {
        REQUIRE(t >= stop.time - kCrossingTol);
        ++windowChecks;
      } else {
        REQUIRE(t == tMax);
        ++clearOfRange;
      }
    }
    if (reach.certified && reach.found) REQUIRE(t <= reach.time + kCrossingTol);

    // against the first impact
    Crossing const impact = FirstCrossing(pair, 0, tMax);
    if (impact.found && impact.certified) {
      ++impacts;
      real const ratio = t / impact.time;
      worstRatio = std::min(worstRatio, ratio);
      ratioSum += ratio;
      if (ratio < 0.5) ++belowHalf;
    }
  }
  real const meanRatio = ratioSum / impacts;
  WARN(Name(kind) << ", " << Name(family) << ": " << startInside << " start inside, "
                  << windowChecks << " stops checked, " << clearOfRange << " clear of range, "
                  << impacts << " impacts (t*/t_impact worst " << worstRatio << ", mean "
                  << meanRatio << ", " << belowHalf << " below 0.5)");
  REQUIRE(belowHalf <= impacts / 100);
  REQUIRE(meanRatio >= 0.75);
  // the checks above must have had cases to judge
  // (two random points rarely meet: the scattered point pairs have the fewest)
  REQUIRE(windowChecks >= kTrials / 100);
  REQUIRE(clearOfRange >= kTrials / 20);
  REQUIRE(impacts >= kTrials / 200);
}

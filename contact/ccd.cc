#include <superdex/contact/ccd.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace superdex::contact {

namespace {

// ---- exact unsigned distances between closed primitives (squared) ----
//
// Every candidate below is the distance of an actual pair of points on the
// two primitives, so round-off can only move the result up to the few ulps
// of evaluating that pair, never to a pair that does not exist.

real PointSegmentDistanceSquared(Real3 const& p, Real3 const& a, Real3 const& b) {
  Real3 const ab = b - a;
  real const lengthSquared = ab.squaredNorm();
  // the projection's parameter on the segment, clamped to the endpoints; a
  // segment of zero length is its point
  real u = 0;
  if (lengthSquared > 0) u = std::clamp((p - a).dot(ab) / lengthSquared, real(0), real(1));
  return (a + u * ab - p).squaredNorm();
}

real PointTriangleDistanceSquared(Real3 const& p, Real3 const& t0, Real3 const& t1,
                                  Real3 const& t2) {
  Real3 const normal = (t1 - t0).cross(t2 - t0);
  real const normalSquared = normal.squaredNorm();
  // the projection of p on the plane lies inside the triangle (on the inner
  // side of all three edges): the distance is the height above the plane
  if (normalSquared > 0) {
    bool const inside = (t1 - t0).cross(p - t0).dot(normal) >= 0 &&
                        (t2 - t1).cross(p - t1).dot(normal) >= 0 &&
                        (t0 - t2).cross(p - t2).dot(normal) >= 0;
    if (inside) {
      real const height = normal.dot(p - t0);
      return height * height / normalSquared;
    }
  }
  // otherwise (or for a triangle of zero area, which is the union of its
  // edges) the closest point is on the boundary
  return std::min({PointSegmentDistanceSquared(p, t0, t1), PointSegmentDistanceSquared(p, t1, t2),
                   PointSegmentDistanceSquared(p, t2, t0)});
}

real SegmentSegmentDistanceSquared(Real3 const& a0, Real3 const& a1, Real3 const& b0,
                                   Real3 const& b1) {
  // the minimum over the parameter square [0, 1]² of |a(s) − b(t)|² is
  // either on the square's boundary (an endpoint against the other segment;
  // always so for parallel segments, where the function is constant along
  // the shared direction) or at the stationary point inside
  real best = std::min({PointSegmentDistanceSquared(a0, b0, b1),
                        PointSegmentDistanceSquared(a1, b0, b1),
                        PointSegmentDistanceSquared(b0, a0, a1),
                        PointSegmentDistanceSquared(b1, a0, a1)});
  Real3 const u = a1 - a0;
  Real3 const v = b1 - b0;
  Real3 const w = a0 - b0;
  real const uu = u.dot(u), vv = v.dot(v), uv = u.dot(v), uw = u.dot(w), vw = v.dot(w);
  real const determinant = uu * vv - uv * uv;
  if (determinant > 0) {
    // the stationary point of |w + s·u − t·v|², clamped: still a pair of
    // points on the segments even where near-parallel segments make it
    // inaccurate, and exact where it matters (inside the square)
    real const s = std::clamp((uv * vw - vv * uw) / determinant, real(0), real(1));
    real const t = std::clamp((uu * vw - uv * uw) / determinant, real(0), real(1));
    best = std::min(best, (w + s * u - t * v).squaredNorm());
  }
  return best;
}

// ---- additive CCD over a pair of vertex sets ----

// The first numA vertices are one primitive, the rest the other; `distance`
// maps the vertex positions to the unsigned distance of the primitives.
template <std::size_t kNum, class Distance>
real AdditiveCcd(std::array<Real3, kNum> const& start, std::array<Real3, kNum> const& displacement,
                 std::size_t numA, Distance const& distance, real thickness, real tMax,
                 real rescale, int maxIterations) {
  if (!(tMax > 0)) return 0;
  rescale = std::clamp(rescale, real(0), real(1));
  real const startGap = distance(start) - thickness;
  if (!(startGap > 0)) return 0;

  // the relative motion: the mean displacement removed (distances do not
  // change under a common translation), then the largest remaining
  // displacement of each side bounds how fast the distance can change
  Real3 mean = Real3::Zero();
  for (Real3 const& d : displacement) mean += d;
  mean /= static_cast<real>(kNum);
  real boundA = 0, boundB = 0;
  for (std::size_t i = 0; i < kNum; ++i) {
    real& bound = i < numA ? boundA : boundB;
    bound = std::max(bound, (displacement[i] - mean).norm());
  }
  real const lipschitz = boundA + boundB;
  if (!(lipschitz > 0)) return tMax;

  // advance by the time the gap needs to fall to the target at the bound's
  // speed, with the exact distance at each advanced time
  real const targetGap = (1 - rescale) * startGap;
  real const stopExcess = kCcdStopFraction * rescale * startGap;
  real excess = startGap - targetGap;
  real t = 0;
  std::array<Real3, kNum> positions;
  for (int iteration = 0; iteration < maxIterations; ++iteration) {
    real const step = excess / lipschitz;
    if (step >= tMax - t) return tMax;
    t += step;
    for (std::size_t i = 0; i < kNum; ++i) positions[i] = start[i] + t * displacement[i];
    excess = distance(positions) - thickness - targetGap;
    if (excess <= stopExcess) return t;
  }
  // the cap: every advanced time keeps the guarantee
  return t;
}

}  // namespace

real PointTriangleCcd(Real3 const& p, Real3 const& t0, Real3 const& t1, Real3 const& t2,
                      Real3 const& dp, Real3 const& dt0, Real3 const& dt1, Real3 const& dt2,
                      real thickness, real tMax, real rescale, int maxIterations) {
  auto const distance = [](std::array<Real3, 4> const& x) {
    return std::sqrt(PointTriangleDistanceSquared(x[0], x[1], x[2], x[3]));
  };
  return AdditiveCcd<4>({p, t0, t1, t2}, {dp, dt0, dt1, dt2}, 1, distance, thickness, tMax,
                        rescale, maxIterations);
}

real EdgeEdgeCcd(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0, Real3 const& eb1,
                 Real3 const& dea0, Real3 const& dea1, Real3 const& deb0, Real3 const& deb1,
                 real thickness, real tMax, real rescale, int maxIterations) {
  auto const distance = [](std::array<Real3, 4> const& x) {
    return std::sqrt(SegmentSegmentDistanceSquared(x[0], x[1], x[2], x[3]));
  };
  return AdditiveCcd<4>({ea0, ea1, eb0, eb1}, {dea0, dea1, deb0, deb1}, 2, distance, thickness,
                        tMax, rescale, maxIterations);
}

real PointEdgeCcd(Real3 const& p, Real3 const& e0, Real3 const& e1, Real3 const& dp,
                  Real3 const& de0, Real3 const& de1, real thickness, real tMax, real rescale,
                  int maxIterations) {
  auto const distance = [](std::array<Real3, 3> const& x) {
    return std::sqrt(PointSegmentDistanceSquared(x[0], x[1], x[2]));
  };
  return AdditiveCcd<3>({p, e0, e1}, {dp, de0, de1}, 1, distance, thickness, tMax, rescale,
                        maxIterations);
}

real PointPointCcd(Real3 const& a, Real3 const& b, Real3 const& da, Real3 const& db,
                   real thickness, real tMax, real rescale, int maxIterations) {
  auto const distance = [](std::array<Real3, 2> const& x) { return (x[0] - x[1]).norm(); };
  return AdditiveCcd<2>({a, b}, {da, db}, 1, distance, thickness, tMax, rescale, maxIterations);
}

real PointPlaneCcd(Real3 const& p, Real3 const& dp, real radius, Real3 const& normal,
                   real offset, real offsetDisplacement, real tMax, real rescale) {
  if (!(tMax > 0)) return 0;
  rescale = std::clamp(rescale, real(0), real(1));
  real const normalLength = normal.norm();
  real const startGap = (normal.dot(p) - offset) / normalLength - radius;
  if (!(startGap > 0)) return 0;
  // the gap is linear: g(t) = g(0) + t·ġ
  real const rate = (normal.dot(dp) - offsetDisplacement) / normalLength;
  if (!(rate < 0)) return tMax;
  return std::min(rescale * startGap / -rate, tMax);
}

real PointSphereCcd(Real3 const& p, Real3 const& dp, real radius, Real3 const& center,
                    Real3 const& dCenter, real sphereRadius, real tMax, real rescale) {
  if (!(tMax > 0)) return 0;
  rescale = std::clamp(rescale, real(0), real(1));
  Real3 const q = p - center;
  Real3 const v = dp - dCenter;
  real const contactDistance = radius + sphereRadius;
  real const startDistance = q.norm();
  real const startGap = startDistance - contactDistance;
  if (!(startGap > 0)) return 0;
  // ‖q + t·v‖² = ρ² with ρ the centre distance at the target gap:
  // a·t² + 2b·t + c = 0 with c = ‖q‖² − ρ² > 0
  real const rho = contactDistance + (1 - rescale) * startGap;
  real const a = v.squaredNorm();
  real const b = q.dot(v);
  real const c = (startDistance - rho) * (startDistance + rho);
  // moving apart or sideways: the distance only grows from t = 0
  if (!(b < 0)) return tMax;
  // the closest approach stays beyond ρ
  real const discriminant = b * b - a * c;
  if (discriminant < 0) return tMax;
  // the smaller root, in the form without cancellation
  return std::min(c / (-b + std::sqrt(discriminant)), tMax);
}

}  // namespace superdex::contact

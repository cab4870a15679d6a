#include <superdex/contact/distance.h>

#include <algorithm>
#include <limits>

#include <superdex/core/so3.h>

#include <algorithm>
#include <array>

namespace superdex::contact {
namespace {

// ------------------------------------------------------------ building blocks
//
// Every distance is a function of a few edge vectors (differences of the
// pair's positions). The derivatives are formed w.r.t. those vectors and
// pulled back to the positions through the constant selection S (y = S x):
// ∇ₓf = Sᵀ∇_y f, ∇ₓ²f = Sᵀ ∇_y²f S.

// The linear map x ↦ y of 3-blocks: block (i, j) of S is coefficients(i, j)·I.
template <int rows, int cols>
Eigen::Matrix<real, 3 * rows, 3 * cols> BlockSelection(
    Eigen::Matrix<real, rows, cols> const& coefficients) {
  Eigen::Matrix<real, 3 * rows, 3 * cols> s = Eigen::Matrix<real, 3 * rows, 3 * cols>::Zero();
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j)
      s.template block<3, 3>(3 * i, 3 * j) = coefficients(i, j) * Real33::Identity();
  return s;
}

template <int m, int n>
ValueGradientHessian<n> PullBack(ValueGradientHessian<m> const& f,
                                 Eigen::Matrix<real, m, n> const& s) {
  ValueGradientHessian<n> r;
  r.value = f.value;
  r.gradient = s.transpose() * f.gradient;
  r.hessian = s.transpose() * f.hessian * s;
  return r;
}

// ‖u × v‖² as a function of (u, v): with n = u × v, dn = −[v]× du + [u]× dv,
// so ∇ = 2 (v × n; n × u) and ∇² = 2 JᵀJ + 2 n·∇²n, J = [−[v]×, [u]×]; the
// bilinear n·(du × dv) has the block −[n]× in (u, v) and [n]× in (v, u).
ValueGradientHessian<6> CrossSquaredNorm(Real3 const& u, Real3 const& v) {
  Real3 const n = u.cross(v);
  ValueGradientHessian<6> c;
  c.value = n.squaredNorm();
  c.gradient << 2 * v.cross(n), 2 * n.cross(u);
  Eigen::Matrix<real, 3, 6> jacobian;
  jacobian << -Hat(v), Hat(u);
  c.hessian = 2 * jacobian.transpose() * jacobian;
  Real33 const nHat = Hat(n);
  c.hessian.block<3, 3>(0, 3) -= 2 * nHat;
  c.hessian.block<3, 3>(3, 0) += 2 * nHat;
  return c;
}

// s = w·(u × v) as a function of (w, u, v): trilinear, so ∇ = (u×v; v×w; w×u)
// and ∇² has the bilinear blocks −[v]× in (w, u), [u]× in (w, v), −[w]× in
// (u, v) and their transposes.
ValueGradientHessian<9> TripleProduct(Real3 const& w, Real3 const& u, Real3 const& v) {
  ValueGradientHessian<9> s;
  s.value = w.dot(u.cross(v));
  s.gradient << u.cross(v), v.cross(w), w.cross(u);
  Real33 const wHat = Hat(w), uHat = Hat(u), vHat = Hat(v);
  s.hessian.block<3, 3>(0, 3) = -vHat;
  s.hessian.block<3, 3>(3, 0) = vHat;
  s.hessian.block<3, 3>(0, 6) = uHat;
  s.hessian.block<3, 3>(6, 0) = -uHat;
  s.hessian.block<3, 3>(3, 6) = -wHat;
  s.hessian.block<3, 3>(6, 3) = wHat;
  return s;
}

template <int n>
ValueGradientHessian<n> Square(ValueGradientHessian<n> const& s) {
  ValueGradientHessian<n> r;
  r.value = s.value * s.value;
  r.gradient = 2 * s.value * s.gradient;
  r.hessian = 2 * (s.gradient * s.gradient.transpose() + s.value * s.hessian);
  return r;
}

// f = N/D from f D = N: ∇f = (∇N − f∇D)/D, ∇²f = (∇²N − f∇²D − ∇f∇Dᵀ − ∇D∇fᵀ)/D.
template <int n>
ValueGradientHessian<n> Quotient(ValueGradientHessian<n> const& num,
                                 ValueGradientHessian<n> const& den) {
  ValueGradientHessian<n> f;
  f.value = num.value / den.value;
  f.gradient = (num.gradient - f.value * den.gradient) / den.value;
  LocalMatrix<n> const cross = f.gradient * den.gradient.transpose();
  f.hessian = (num.hessian - f.value * den.hessian - cross - cross.transpose()) / den.value;
  return f;
}

// s²/‖u × v‖², s = w·(u × v): the squared distance from the point w (relative
// to the plane's origin) to the plane spanned by u and v, and the squared
// distance between two lines with directions u, v whose origins differ by w.
ValueGradientHessian<9> PlaneDistance2(Real3 const& w, Real3 const& u, Real3 const& v) {
  ValueGradientHessian<6> const cross = CrossSquaredNorm(u, v);
  ValueGradientHessian<9> den;
  den.value = cross.value;
  den.gradient.tail<6>() = cross.gradient;
  den.hessian.bottomRightCorner<6, 6>() = cross.hessian;
  return Quotient(Square(TripleProduct(w, u, v)), den);
}

// ‖u × v‖²/‖v − u‖² with u = e0 − p, v = e1 − p: the squared distance from p
// to the line through e0 and e1.
ValueGradientHessian<6> LineDistance2(Real3 const& u, Real3 const& v) {
  Real3 const e = v - u;
  ValueGradientHessian<6> den;
  den.value = e.squaredNorm();
  den.gradient << -2 * e, 2 * e;
  den.hessian = BlockSelection<2, 2>((Matrix2() << 2, -2, -2, 2).finished());
  return Quotient(CrossSquaredNorm(u, v), den);
}

// Selections of the four distances (x in the pair's coordinate order).
// (e0 − p, e1 − p) of (p, e0, e1)
Eigen::Matrix<real, 6, 9> const& PointLineSelection() {
  static Eigen::Matrix<real, 6, 9> const s =
      BlockSelection<2, 3>((Eigen::Matrix<real, 2, 3>() << -1, 1, 0,  //
                            -1, 0, 1)
                               .finished());
  return s;
}
// (p − t0, t1 − t0, t2 − t0) of (p, t0, t1, t2)
Eigen::Matrix<real, 9, 12> const& PointPlaneSelection() {
  static Eigen::Matrix<real, 9, 12> const s =
      BlockSelection<3, 4>((Eigen::Matrix<real, 3, 4>() << 1, -1, 0, 0,  //
                            0, -1, 1, 0,                                 //
                            0, -1, 0, 1)
                               .finished());
  return s;
}
// (eb0 − ea0, ea1 − ea0, eb1 − eb0) of (ea0, ea1, eb0, eb1)
Eigen::Matrix<real, 9, 12> const& LineLineSelection() {
  static Eigen::Matrix<real, 9, 12> const s =
      BlockSelection<3, 4>((Eigen::Matrix<real, 3, 4>() << -1, 0, 1, 0,  //
                            -1, 1, 0, 0,                                 //
                            0, 0, -1, 1)
                               .finished());
  return s;
}
// (ea1 − ea0, eb1 − eb0) of (ea0, ea1, eb0, eb1)
Eigen::Matrix<real, 6, 12> const& EdgeDirectionsSelection() {
  static Eigen::Matrix<real, 6, 12> const s =
      BlockSelection<2, 4>((Eigen::Matrix<real, 2, 4>() << -1, 1, 0, 0,  //
                            0, 0, -1, 1)
                               .finished());
  return s;
}

ValueGradientHessian<6> PointPointLocal(Real3 const& p0, Real3 const& p1) {
  ValueGradientHessian<6> f;
  Real3 const d = p0 - p1;
  f.value = d.squaredNorm();
  f.gradient << 2 * d, -2 * d;
  f.hessian = BlockSelection<2, 2>((Matrix2() << 2, -2, -2, 2).finished());
  return f;
}
ValueGradientHessian<9> PointLineLocal(Real3 const& p, Real3 const& e0, Real3 const& e1) {
  return PullBack(LineDistance2(e0 - p, e1 - p), PointLineSelection());
}
ValueGradientHessian<12> PointPlaneLocal(Real3 const& p, Real3 const& t0, Real3 const& t1,
                                         Real3 const& t2) {
  return PullBack(PlaneDistance2(p - t0, t1 - t0, t2 - t0), PointPlaneSelection());
}
ValueGradientHessian<12> LineLineLocal(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                                       Real3 const& eb1) {
  return PullBack(PlaneDistance2(eb0 - ea0, ea1 - ea0, eb1 - eb0), LineLineSelection());
}

// Places the derivatives of a function of m/3 of the pair's points (`nodes`,
// indices of the pair's points in order) into the pair's n coordinates.
template <int n, int m>
ValueGradientHessian<n> Scatter(ValueGradientHessian<m> const& local,
                                std::array<int, m / 3> const& nodes) {
  ValueGradientHessian<n> r;
  r.value = local.value;
  for (int i = 0; i < m / 3; ++i) {
    r.gradient.template segment<3>(3 * nodes[i]) = local.gradient.template segment<3>(3 * i);
    for (int j = 0; j < m / 3; ++j)
      r.hessian.template block<3, 3>(3 * nodes[i], 3 * nodes[j]) =
          local.hessian.template block<3, 3>(3 * i, 3 * j);
  }
  return r;
}

// --------------------------------------------------------- classification

// u and v span a plane (a triangle, or two edges' directions) whose sine of
// the angle is above the parallel threshold; n = u × v.
bool SpansPlane(Real3 const& u, Real3 const& v, Real3 const& n) {
  return n.squaredNorm() > kParallelSin2 * u.squaredNorm() * v.squaredNorm();
}

// The closest point of the segment (a, b) to p: a + t (b − a), t ∈ [0, 1]
// (t = 0 for a = b), and its squared distance.
struct SegmentPoint {
  real t = 0;
  real distance2 = 0;
};
SegmentPoint ClosestOnSegment(Real3 const& p, Real3 const& a, Real3 const& b) {
  Real3 const e = b - a;
  real const ee = e.squaredNorm();
  SegmentPoint s;
  if (ee > 0) s.t = std::clamp((p - a).dot(e) / ee, real(0), real(1));
  s.distance2 = (p - (a + s.t * e)).squaredNorm();
  return s;
}

// The closest feature of the triangle's boundary to p, with the barycentric
// coordinates (β1, β2) of the closest point.
struct BoundaryPoint {
  PointTriangleType type = PointTriangleType::P_T0;
  Vector2 beta = Vector2::Zero();
};
BoundaryPoint ClosestOnTriangleBoundary(Real3 const& p, Real3 const& t0, Real3 const& t1,
                                        Real3 const& t2) {
  struct Edge {
    Real3 const& a;
    Real3 const& b;
    PointTriangleType atA, atB, interior;
  };
  std::array<Edge, 3> const edges = {
      Edge{t0, t1, PointTriangleType::P_T0, PointTriangleType::P_T1, PointTriangleType::P_E0},
      Edge{t1, t2, PointTriangleType::P_T1, PointTriangleType::P_T2, PointTriangleType::P_E1},
      Edge{t2, t0, PointTriangleType::P_T2, PointTriangleType::P_T0, PointTriangleType::P_E2}};
  int best = 0;
  SegmentPoint closest = ClosestOnSegment(p, t0, t1);
  for (int i = 1; i < 3; ++i) {
    SegmentPoint const s = ClosestOnSegment(p, edges[i].a, edges[i].b);
    if (s.distance2 < closest.distance2) best = i, closest = s;
  }
  Edge const& edge = edges[best];
  BoundaryPoint r;
  r.type = closest.t <= 0 ? edge.atA : closest.t >= 1 ? edge.atB : edge.interior;
  // the closest point a + t (b − a) in the triangle's coordinates
  real const t = closest.t;
  if (best == 0) r.beta = Vector2(t, 0);
  if (best == 1) r.beta = Vector2(1 - t, t);
  if (best == 2) r.beta = Vector2(0, 1 - t);
  return r;
}

// (β1, β2) of p's projection onto the plane of a non-degenerate triangle, by
// Cramer's rule with the normal: β1 = ((w × v)·n)/‖n‖², β2 = ((u × w)·n)/‖n‖².
Vector2 PlaneCoordinates(Real3 const& w, Real3 const& u, Real3 const& v, Real3 const& n) {
  real const nn = n.squaredNorm();
  return Vector2(w.cross(v).dot(n) / nn, u.cross(w).dot(n) / nn);
}

// (α, β) of the closest points ea0 + α u, eb0 + β v of two non-parallel
// lines, r = eb0 − ea0: α u − β v is r's projection onto span(u, v).
Vector2 LineCoordinates(Real3 const& r, Real3 const& u, Real3 const& v, Real3 const& n) {
  real const nn = n.squaredNorm();
  return Vector2(r.cross(v).dot(n) / nn, r.cross(u).dot(n) / nn);
}

// ------------------------------------------------------------ tangent bases

// A unit vector orthogonal to the unit vector a, crossing it with the
// coordinate axis least aligned with it.
Real3 AnyUnitPerpendicular(Real3 const& a) {
  Eigen::Index axis = 0;
  a.cwiseAbs().minCoeff(&axis);
  return a.cross(Real3::Unit(axis)).normalized();
}

// A basis of the plane orthogonal to `normal` (orthogonal to the z axis when
// normal = 0).
TangentBasis BasisOrthogonalTo(Real3 const& normal) {
  real const length = normal.norm();
  Real3 const unit = length > 0 ? Real3(normal / length) : Real3::UnitZ();
  Real3 const first = AnyUnitPerpendicular(unit);
  TangentBasis basis;
  basis << first, unit.cross(first);
  return basis;
}

// The basis (d̂, n̂ × d̂) with d̂ = direction/‖direction‖: orthogonal to the
// part of `normal` orthogonal to `direction`. Falls back to any unit vector
// orthogonal to d̂ when that part vanishes (to 1e-12 of ‖normal‖), and to
// BasisOrthogonalTo(normal) when direction = 0.
TangentBasis BasisAlong(Real3 const& direction, Real3 const& normal) {
  real const length = direction.norm();
  if (!(length > 0)) return BasisOrthogonalTo(normal);
  Real3 const first = direction / length;
  Real3 second = normal.cross(first);
  real const secondLength = second.norm();
  second = secondLength > 1e-12 * normal.norm() ? Real3(second / secondLength)
                                                : AnyUnitPerpendicular(first);
  TangentBasis basis;
  basis << first, second;
  return basis;
}

}  // namespace

// ------------------------------------------------------------ point–point

real PointPointDistance2(Real3 const& p0, Real3 const& p1) {
  return (p0 - p1).squaredNorm();
}
Vector6 PointPointDistance2Gradient(Real3 const& p0, Real3 const& p1) {
  return PointPointLocal(p0, p1).gradient;
}
Matrix6 PointPointDistance2Hessian(Real3 const& p0, Real3 const& p1) {
  return PointPointLocal(p0, p1).hessian;
}

// ------------------------------------------------------------- point–line

real PointLineDistance2(Real3 const& p, Real3 const& e0, Real3 const& e1) {
  return (e0 - p).cross(e1 - p).squaredNorm() / (e1 - e0).squaredNorm();
}
Vector9 PointLineDistance2Gradient(Real3 const& p, Real3 const& e0, Real3 const& e1) {
  return PointLineLocal(p, e0, e1).gradient;
}
Matrix9 PointLineDistance2Hessian(Real3 const& p, Real3 const& e0, Real3 const& e1) {
  return PointLineLocal(p, e0, e1).hessian;
}

// ------------------------------------------------------------ point–plane

real PointPlaneDistance2(Real3 const& p, Real3 const& t0, Real3 const& t1, Real3 const& t2) {
  Real3 const n = (t1 - t0).cross(t2 - t0);
  real const s = (p - t0).dot(n);
  return s * s / n.squaredNorm();
}
Vector12 PointPlaneDistance2Gradient(Real3 const& p, Real3 const& t0, Real3 const& t1,
                                     Real3 const& t2) {
  return PointPlaneLocal(p, t0, t1, t2).gradient;
}
Matrix12 PointPlaneDistance2Hessian(Real3 const& p, Real3 const& t0, Real3 const& t1,
                                    Real3 const& t2) {
  return PointPlaneLocal(p, t0, t1, t2).hessian;
}

// -------------------------------------------------------------- line–line

real LineLineDistance2(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0, Real3 const& eb1) {
  Real3 const n = (ea1 - ea0).cross(eb1 - eb0);
  real const s = (eb0 - ea0).dot(n);
  return s * s / n.squaredNorm();
}
Vector12 LineLineDistance2Gradient(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                                   Real3 const& eb1) {
  return LineLineLocal(ea0, ea1, eb0, eb1).gradient;
}
Matrix12 LineLineDistance2Hessian(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                                  Real3 const& eb1) {
  return LineLineLocal(ea0, ea1, eb0, eb1).hessian;
}

// --------------------------------------------------------- classification

PointEdgeType PointEdgeDistanceType(Real3 const& p, Real3 const& e0, Real3 const& e1) {
  Real3 const e = e1 - e0;
  real const ee = e.squaredNorm();
  if (!(ee > 0)) return PointEdgeType::P_E0;
  real const t = (p - e0).dot(e);
  if (t <= 0) return PointEdgeType::P_E0;
  if (t >= ee) return PointEdgeType::P_E1;
  return PointEdgeType::P_E;
}

PointTriangleType PointTriangleDistanceType(Real3 const& p, Real3 const& t0, Real3 const& t1,
                                            Real3 const& t2) {
  Real3 const u = t1 - t0, v = t2 - t0, n = u.cross(v);
  // the projection onto the plane, when it falls in the closed triangle
  if (SpansPlane(u, v, n)) {
    Vector2 const beta = PlaneCoordinates(p - t0, u, v, n);
    if (beta[0] >= 0 && beta[1] >= 0 && beta[0] + beta[1] <= 1) return PointTriangleType::P_T;
  }
  // otherwise (or for a degenerate triangle) the closest point of the boundary
  return ClosestOnTriangleBoundary(p, t0, t1, t2).type;
}

EdgeEdgeType EdgeEdgeDistanceType(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                                  Real3 const& eb1) {
  Real3 const u = ea1 - ea0, v = eb1 - eb0, n = u.cross(v);
  // the lines' closest points, when both fall on the closed segments
  if (SpansPlane(u, v, n)) {
    Vector2 const t = LineCoordinates(eb0 - ea0, u, v, n);
    if (t[0] >= 0 && t[0] <= 1 && t[1] >= 0 && t[1] <= 1) return EdgeEdgeType::EA_EB;
  }
  // otherwise one closest point is an end point: the closest of the four end
  // point–segment pairs (exact for parallel edges as well)
  struct Candidate {
    SegmentPoint closest;
    EdgeEdgeType atStart, atEnd, interior;
  };
  std::array<Candidate, 4> const candidates = {
      Candidate{ClosestOnSegment(ea0, eb0, eb1), EdgeEdgeType::EA0_EB0, EdgeEdgeType::EA0_EB1,
                EdgeEdgeType::EA0_EB},
      Candidate{ClosestOnSegment(ea1, eb0, eb1), EdgeEdgeType::EA1_EB0, EdgeEdgeType::EA1_EB1,
                EdgeEdgeType::EA1_EB},
      Candidate{ClosestOnSegment(eb0, ea0, ea1), EdgeEdgeType::EA0_EB0, EdgeEdgeType::EA1_EB0,
                EdgeEdgeType::EA_EB0},
      Candidate{ClosestOnSegment(eb1, ea0, ea1), EdgeEdgeType::EA0_EB1, EdgeEdgeType::EA1_EB1,
                EdgeEdgeType::EA_EB1}};
  int best = 0;
  for (int i = 1; i < 4; ++i)
    if (candidates[i].closest.distance2 < candidates[best].closest.distance2) best = i;
  Candidate const& c = candidates[best];
  return c.closest.t <= 0 ? c.atStart : c.closest.t >= 1 ? c.atEnd : c.interior;
}

// ------------------------------------------------- dispatch by pair type

ValueGradientHessian<9> PointEdgeDistance2Derivatives(Real3 const& p, Real3 const& e0,
                                                      Real3 const& e1, PointEdgeType type) {
  switch (type) {
    case PointEdgeType::P_E0:
      return Scatter<9>(PointPointLocal(p, e0), {0, 1});
    case PointEdgeType::P_E1:
      return Scatter<9>(PointPointLocal(p, e1), {0, 2});
    case PointEdgeType::P_E:
      return PointLineLocal(p, e0, e1);
  }
  return {};
}

ValueGradientHessian<12> PointTriangleDistance2Derivatives(Real3 const& p, Real3 const& t0,
                                                           Real3 const& t1, Real3 const& t2,
                                                           PointTriangleType type) {
  switch (type) {
    case PointTriangleType::P_T0:
      return Scatter<12>(PointPointLocal(p, t0), {0, 1});
    case PointTriangleType::P_T1:
      return Scatter<12>(PointPointLocal(p, t1), {0, 2});
    case PointTriangleType::P_T2:
      return Scatter<12>(PointPointLocal(p, t2), {0, 3});
    case PointTriangleType::P_E0:
      return Scatter<12>(PointLineLocal(p, t0, t1), {0, 1, 2});
    case PointTriangleType::P_E1:
      return Scatter<12>(PointLineLocal(p, t1, t2), {0, 2, 3});
    case PointTriangleType::P_E2:
      return Scatter<12>(PointLineLocal(p, t2, t0), {0, 3, 1});
    case PointTriangleType::P_T:
      return PointPlaneLocal(p, t0, t1, t2);
  }
  return {};
}

ValueGradientHessian<12> EdgeEdgeDistance2Derivatives(Real3 const& ea0, Real3 const& ea1,
                                                      Real3 const& eb0, Real3 const& eb1,
                                                      EdgeEdgeType type) {
  switch (type) {
    case EdgeEdgeType::EA0_EB0:
      return Scatter<12>(PointPointLocal(ea0, eb0), {0, 2});
    case EdgeEdgeType::EA0_EB1:
      return Scatter<12>(PointPointLocal(ea0, eb1), {0, 3});
    case EdgeEdgeType::EA1_EB0:
      return Scatter<12>(PointPointLocal(ea1, eb0), {1, 2});
    case EdgeEdgeType::EA1_EB1:
      return Scatter<12>(PointPointLocal(ea1, eb1), {1, 3});
    case EdgeEdgeType::EA_EB0:
      return Scatter<12>(PointLineLocal(eb0, ea0, ea1), {2, 0, 1});
    case EdgeEdgeType::EA_EB1:
      return Scatter<12>(PointLineLocal(eb1, ea0, ea1), {3, 0, 1});
    case EdgeEdgeType::EA0_EB:
      return Scatter<12>(PointLineLocal(ea0, eb0, eb1), {0, 2, 3});
    case EdgeEdgeType::EA1_EB:
      return Scatter<12>(PointLineLocal(ea1, eb0, eb1), {1, 2, 3});
    case EdgeEdgeType::EA_EB:
      return LineLineLocal(ea0, ea1, eb0, eb1);
  }
  return {};
}

real PointEdgeDistance2(Real3 const& p, Real3 const& e0, Real3 const& e1, PointEdgeType type) {
  switch (type) {
    case PointEdgeType::P_E0:
      return PointPointDistance2(p, e0);
    case PointEdgeType::P_E1:
      return PointPointDistance2(p, e1);
    case PointEdgeType::P_E:
      return PointLineDistance2(p, e0, e1);
  }
  return 0;
}
Vector9 PointEdgeDistance2Gradient(Real3 const& p, Real3 const& e0, Real3 const& e1,
                                   PointEdgeType type) {
  return PointEdgeDistance2Derivatives(p, e0, e1, type).gradient;
}
Matrix9 PointEdgeDistance2Hessian(Real3 const& p, Real3 const& e0, Real3 const& e1,
                                  PointEdgeType type) {
  return PointEdgeDistance2Derivatives(p, e0, e1, type).hessian;
}

real PointTriangleDistance2(Real3 const& p, Real3 const& t0, Real3 const& t1, Real3 const& t2,
                            PointTriangleType type) {
  switch (type) {
    case PointTriangleType::P_T0:
      return PointPointDistance2(p, t0);
    case PointTriangleType::P_T1:
      return PointPointDistance2(p, t1);
    case PointTriangleType::P_T2:
      return PointPointDistance2(p, t2);
    case PointTriangleType::P_E0:
      return PointLineDistance2(p, t0, t1);
    case PointTriangleType::P_E1:
      return PointLineDistance2(p, t1, t2);
    case PointTriangleType::P_E2:
      return PointLineDistance2(p, t2, t0);
    case PointTriangleType::P_T:
      return PointPlaneDistance2(p, t0, t1, t2);
  }
  return 0;
}
Vector12 PointTriangleDistance2Gradient(Real3 const& p, Real3 const& t0, Real3 const& t1,
                                        Real3 const& t2, PointTriangleType type) {
  return PointTriangleDistance2Derivatives(p, t0, t1, t2, type).gradient;
}
Matrix12 PointTriangleDistance2Hessian(Real3 const& p, Real3 const& t0, Real3 const& t1,
                                       Real3 const& t2, PointTriangleType type) {
  return PointTriangleDistance2Derivatives(p, t0, t1, t2, type).hessian;
}

real EdgeEdgeDistance2(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0, Real3 const& eb1,
                       EdgeEdgeType type) {
  switch (type) {
    case EdgeEdgeType::EA0_EB0:
      return PointPointDistance2(ea0, eb0);
    case EdgeEdgeType::EA0_EB1:
      return PointPointDistance2(ea0, eb1);
    case EdgeEdgeType::EA1_EB0:
      return PointPointDistance2(ea1, eb0);
    case EdgeEdgeType::EA1_EB1:
      return PointPointDistance2(ea1, eb1);
    case EdgeEdgeType::EA_EB0:
      return PointLineDistance2(eb0, ea0, ea1);
    case EdgeEdgeType::EA_EB1:
      return PointLineDistance2(eb1, ea0, ea1);
    case EdgeEdgeType::EA0_EB:
      return PointLineDistance2(ea0, eb0, eb1);
    case EdgeEdgeType::EA1_EB:
      return PointLineDistance2(ea1, eb0, eb1);
    case EdgeEdgeType::EA_EB:
      return LineLineDistance2(ea0, ea1, eb0, eb1);
  }
  return 0;
}
Vector12 EdgeEdgeDistance2Gradient(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                                   Real3 const& eb1, EdgeEdgeType type) {
  return EdgeEdgeDistance2Derivatives(ea0, ea1, eb0, eb1, type).gradient;
}
Matrix12 EdgeEdgeDistance2Hessian(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                                  Real3 const& eb1, EdgeEdgeType type) {
  return EdgeEdgeDistance2Derivatives(ea0, ea1, eb0, eb1, type).hessian;
}

real PointEdgeDistance2(Real3 const& p, Real3 const& e0, Real3 const& e1) {
  return PointEdgeDistance2(p, e0, e1, PointEdgeDistanceType(p, e0, e1));
}
real PointTriangleDistance2(Real3 const& p, Real3 const& t0, Real3 const& t1, Real3 const& t2) {
  return PointTriangleDistance2(p, t0, t1, t2, PointTriangleDistanceType(p, t0, t1, t2));
}
real EdgeEdgeDistance2(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0, Real3 const& eb1) {
  return EdgeEdgeDistance2(ea0, ea1, eb0, eb1, EdgeEdgeDistanceType(ea0, ea1, eb0, eb1));
}

// ------------------------------------------------- edge–edge mollifier

real EdgeEdgeMollifierThreshold(Real3 const& ea0Rest, Real3 const& ea1Rest, Real3 const& eb0Rest,
                                Real3 const& eb1Rest) {
  return 1e-3 * (ea1Rest - ea0Rest).squaredNorm() * (eb1Rest - eb0Rest).squaredNorm();
}

real EdgeEdgeCrossSquaredNorm(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                              Real3 const& eb1) {
  return (ea1 - ea0).cross(eb1 - eb0).squaredNorm();
}

real EdgeEdgeMollifier(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0, Real3 const& eb1,
                       real threshold) {
  real const c = EdgeEdgeCrossSquaredNorm(ea0, ea1, eb0, eb1);
  if (!(c < threshold)) return 1;
  real const x = c / threshold;
  return x * (2 - x);
}

ValueGradientHessian<12> EdgeEdgeMollifierDerivatives(Real3 const& ea0, Real3 const& ea1,
                                                      Real3 const& eb0, Real3 const& eb1,
                                                      real threshold) {
  ValueGradientHessian<12> m;
  m.value = 1;
  if (!(EdgeEdgeCrossSquaredNorm(ea0, ea1, eb0, eb1) < threshold)) return m;
  // m(c) = x (2 − x), x = c/ε×: m′ = 2(1 − x)/ε×, m″ = −2/ε×²
  ValueGradientHessian<12> const c =
      PullBack(CrossSquaredNorm(ea1 - ea0, eb1 - eb0), EdgeDirectionsSelection());
  real const x = c.value / threshold;
  real const slope = 2 * (1 - x) / threshold;
  real const curvature = -2 / (threshold * threshold);
  m.value = x * (2 - x);
  m.gradient = slope * c.gradient;
  m.hessian = curvature * c.gradient * c.gradient.transpose() + slope * c.hessian;
  return m;
}
Vector12 EdgeEdgeMollifierGradient(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                                   Real3 const& eb1, real threshold) {
  return EdgeEdgeMollifierDerivatives(ea0, ea1, eb0, eb1, threshold).gradient;
}
Matrix12 EdgeEdgeMollifierHessian(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                                  Real3 const& eb1, real threshold) {
  return EdgeEdgeMollifierDerivatives(ea0, ea1, eb0, eb1, threshold).hessian;
}

// ------------------------------------------- closest points and tangents

TangentBasis PointPointTangentBasis(Real3 const& p0, Real3 const& p1) {
  return BasisOrthogonalTo(p0 - p1);
}

Eigen::Matrix<real, 3, 6> PointPointDisplacementWeights() {
  Eigen::Matrix<real, 3, 6> gamma;
  gamma << Real33::Identity(), -Real33::Identity();
  return gamma;
}

real PointEdgeClosestPointParameter(Real3 const& p, Real3 const& e0, Real3 const& e1) {
  Real3 const e = e1 - e0;
  real const ee = e.squaredNorm();
  return ee > 0 ? (p - e0).dot(e) / ee : 0;
}

TangentBasis PointEdgeTangentBasis(Real3 const& p, Real3 const& e0, Real3 const& e1) {
  Real3 const e = e1 - e0;
  if (!(e.squaredNorm() > 0)) return PointPointTangentBasis(p, e0);
  // p − e0 has the point–line normal as its part orthogonal to e
  return BasisAlong(e, p - e0);
}

Eigen::Matrix<real, 3, 9> PointEdgeDisplacementWeights(real alpha) {
  Eigen::Matrix<real, 3, 9> gamma;
  gamma << Real33::Identity(), -(1 - alpha) * Real33::Identity(), -alpha * Real33::Identity();
  return gamma;
}

Vector2 PointTriangleClosestPointCoordinates(Real3 const& p, Real3 const& t0, Real3 const& t1,
                                             Real3 const& t2) {
  Real3 const u = t1 - t0, v = t2 - t0, n = u.cross(v);
  if (SpansPlane(u, v, n)) return PlaneCoordinates(p - t0, u, v, n);
  return ClosestOnTriangleBoundary(p, t0, t1, t2).beta;
}

TangentBasis PointTriangleTangentBasis(Real3 const& t0, Real3 const& t1, Real3 const& t2) {
  Real3 const u = t1 - t0;
  return BasisAlong(u, u.cross(t2 - t0));
}

Eigen::Matrix<real, 3, 12> PointTriangleDisplacementWeights(Vector2 const& beta) {
  Eigen::Matrix<real, 3, 12> gamma;
  gamma << Real33::Identity(), -(1 - beta[0] - beta[1]) * Real33::Identity(),
      -beta[0] * Real33::Identity(), -beta[1] * Real33::Identity();
  return gamma;
}

Vector2 EdgeEdgeClosestPointParameters(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                                       Real3 const& eb1) {
  Real3 const u = ea1 - ea0, v = eb1 - eb0, n = u.cross(v);
  if (SpansPlane(u, v, n)) return LineCoordinates(eb0 - ea0, u, v, n);
  return Vector2(0, PointEdgeClosestPointParameter(ea0, eb0, eb1));
}

TangentBasis EdgeEdgeTangentBasis(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                                  Real3 const& eb1) {
  Real3 const u = ea1 - ea0;
  return BasisAlong(u, u.cross(eb1 - eb0));
}

Eigen::Matrix<real, 3, 12> EdgeEdgeDisplacementWeights(Vector2 const& alphaBeta) {
  real const alpha = alphaBeta[0], beta = alphaBeta[1];
  Eigen::Matrix<real, 3, 12> gamma;
  gamma << (1 - alpha) * Real33::Identity(), alpha * Real33::Identity(),
      -(1 - beta) * Real33::Identity(), -beta * Real33::Identity();
  return gamma;
}

TangentFrame<9> PointEdgeTangentFrame(Real3 const& p, Real3 const& e0, Real3 const& e1,
                                      PointEdgeType type) {
  TangentFrame<9> frame;
  real alpha = 0;
  switch (type) {
    case PointEdgeType::P_E0:
      frame.basis = PointPointTangentBasis(p, e0);
      break;
    case PointEdgeType::P_E1:
      alpha = 1;
      frame.basis = PointPointTangentBasis(p, e1);
      break;
    case PointEdgeType::P_E:
      alpha = PointEdgeClosestPointParameter(p, e0, e1);
      frame.basis = PointEdgeTangentBasis(p, e0, e1);
      break;
  }
  frame.weights = PointEdgeDisplacementWeights(alpha);
  return frame;
}

TangentFrame<12> PointTriangleTangentFrame(Real3 const& p, Real3 const& t0, Real3 const& t1,
                                           Real3 const& t2, PointTriangleType type) {
  TangentFrame<12> frame;
  Vector2 beta = Vector2::Zero();
  switch (type) {
    case PointTriangleType::P_T0:
      frame.basis = PointPointTangentBasis(p, t0);
      break;
    case PointTriangleType::P_T1:
      beta = Vector2(1, 0);
      frame.basis = PointPointTangentBasis(p, t1);
      break;
    case PointTriangleType::P_T2:
      beta = Vector2(0, 1);
      frame.basis = PointPointTangentBasis(p, t2);
      break;
    case PointTriangleType::P_E0: {  // t0 + α (t1 − t0)
      real const alpha = PointEdgeClosestPointParameter(p, t0, t1);
      beta = Vector2(alpha, 0);
      frame.basis = PointEdgeTangentBasis(p, t0, t1);
      break;
    }
    case PointTriangleType::P_E1: {  // t1 + α (t2 − t1)
      real const alpha = PointEdgeClosestPointParameter(p, t1, t2);
      beta = Vector2(1 - alpha, alpha);
      frame.basis = PointEdgeTangentBasis(p, t1, t2);
      break;
    }
    case PointTriangleType::P_E2: {  // t2 + α (t0 − t2)
      real const alpha = PointEdgeClosestPointParameter(p, t2, t0);
      beta = Vector2(0, 1 - alpha);
      frame.basis = PointEdgeTangentBasis(p, t2, t0);
      break;
    }
    case PointTriangleType::P_T:
      beta = PointTriangleClosestPointCoordinates(p, t0, t1, t2);
      frame.basis = PointTriangleTangentBasis(t0, t1, t2);
      break;
  }
  frame.weights = PointTriangleDisplacementWeights(beta);
  return frame;
}

TangentFrame<12> EdgeEdgeTangentFrame(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                                      Real3 const& eb1, EdgeEdgeType type) {
  TangentFrame<12> frame;
  Vector2 alphaBeta = Vector2::Zero();
  switch (type) {
    case EdgeEdgeType::EA0_EB0:
      frame.basis = PointPointTangentBasis(ea0, eb0);
      break;
    case EdgeEdgeType::EA0_EB1:
      alphaBeta = Vector2(0, 1);
      frame.basis = PointPointTangentBasis(ea0, eb1);
      break;
    case EdgeEdgeType::EA1_EB0:
      alphaBeta = Vector2(1, 0);
      frame.basis = PointPointTangentBasis(ea1, eb0);
      break;
    case EdgeEdgeType::EA1_EB1:
      alphaBeta = Vector2(1, 1);
      frame.basis = PointPointTangentBasis(ea1, eb1);
      break;
    case EdgeEdgeType::EA_EB0:
      alphaBeta = Vector2(PointEdgeClosestPointParameter(eb0, ea0, ea1), 0);
      frame.basis = PointEdgeTangentBasis(eb0, ea0, ea1);
      break;
    case EdgeEdgeType::EA_EB1:
      alphaBeta = Vector2(PointEdgeClosestPointParameter(eb1, ea0, ea1), 1);
      frame.basis = PointEdgeTangentBasis(eb1, ea0, ea1);
      break;
    case EdgeEdgeType::EA0_EB:
      alphaBeta = Vector2(0, PointEdgeClosestPointParameter(ea0, eb0, eb1));
      frame.basis = PointEdgeTangentBasis(ea0, eb0, eb1);
      break;
    case EdgeEdgeType::EA1_EB:
      alphaBeta = Vector2(1, PointEdgeClosestPointParameter(ea1, eb0, eb1));
      frame.basis = PointEdgeTangentBasis(ea1, eb0, eb1);
      break;
    case EdgeEdgeType::EA_EB:
      alphaBeta = EdgeEdgeClosestPointParameters(ea0, ea1, eb0, eb1);
      frame.basis = EdgeEdgeTangentBasis(ea0, ea1, eb0, eb1);
      break;
  }
  frame.weights = EdgeEdgeDisplacementWeights(alphaBeta);
  return frame;
}

bool SegmentMeetsTriangle(Real3 const& s0, Real3 const& s1, Real3 const& t0, Real3 const& t1, Real3 const& t2) {
  auto orient = [](Real3 const& a, Real3 const& b, Real3 const& c, Real3 const& d) {
    return (b - a).cross(c - a).dot(d - a);
  };
  // volumes below round-off of the primitives' size count as zero: a flat
  // sheet's edges and triangles are coplanar, not crossing by noise
  real const size = std::max({(s1 - s0).norm(), (t1 - t0).norm(), (t2 - t1).norm(), (t0 - t2).norm()});
  real const eps = 64 * std::numeric_limits<real>::epsilon() * size * size * size;
  auto sign = [&](real v) { return v > eps ? 1 : v < -eps ? -1 : 0; };
  int const v0 = sign(orient(t0, t1, t2, s0)), v1 = sign(orient(t0, t1, t2, s1));
  if (v0 * v1 > 0) return false;
  real const touch = 64 * std::numeric_limits<real>::epsilon() * size;
  if (v0 == 0 || v1 == 0) {  // an end on the plane, or the whole segment in it: where the distance is zero
    real d2 = std::min(v0 == 0 ? PointTriangleDistance2(s0, t0, t1, t2) : real(1e300),
                       v1 == 0 ? PointTriangleDistance2(s1, t0, t1, t2) : real(1e300));
    if (v0 == 0 && v1 == 0)
      d2 = std::min({d2, EdgeEdgeDistance2(s0, s1, t0, t1), EdgeEdgeDistance2(s0, s1, t1, t2),
                     EdgeEdgeDistance2(s0, s1, t2, t0)});
    return d2 <= touch * touch;
  }
  int const a = sign(orient(s0, s1, t0, t1)), b = sign(orient(s0, s1, t1, t2)), c = sign(orient(s0, s1, t2, t0));
  return (a >= 0 && b >= 0 && c >= 0) || (a <= 0 && b <= 0 && c <= 0);
}

}  // namespace superdex::contact

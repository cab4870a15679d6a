// Unsigned squared distances between contact primitives, with closed-form
// gradients and Hessians, the classification of the closest features, the
// edge–edge mollifier and the tangent frames of friction (incremental
// potential contact: Li et al. 2020, "Incremental Potential Contact"; Li et
// al. 2021, "Codimensional Incremental Potential Contact").
//
// Conventions
//   Positions are in m, squared distances in m². Squared distances are used
//   because they are smooth (polynomial over a non-vanishing denominator)
//   where the distance itself is not.
//   Degrees of freedom are node-major: a point–triangle pair (p, t0, t1, t2)
//   has the 12 coordinates x = (p; t0; t1; t2), an edge–edge pair
//   (ea0, ea1, eb0, eb1) has x = (ea0; ea1; eb0; eb1), a point–edge pair
//   (p, e0, e1) has 9, a point–point pair (p0, p1) has 6. Gradients are
//   fixed-size vectors, Hessians fixed-size symmetric matrices, in that order.
//
// The four smooth distances (each the distance to an unbounded feature):
//   point–point    d² = ‖p0 − p1‖²
//   point–line     d² = ‖(e0 − p) × (e1 − p)‖² / ‖e1 − e0‖²
//   point–plane    d² = ((p − t0)·n)² / ‖n‖²,           n = (t1 − t0) × (t2 − t0)
//   line–line      d² = ((eb0 − ea0)·n)² / ‖n‖²,        n = (ea1 − ea0) × (eb1 − eb0)
// Their derivatives are the quotient rule applied to polynomial numerators
// and denominators (triple and cross products), not automatic or finite
// differentiation.
//
// The distance between closed primitives (a triangle with its boundary, a
// segment with its end points) is one of those four, chosen by the
// classification (PointTriangleDistanceType, EdgeEdgeDistanceType,
// PointEdgeDistanceType); the type-dispatching functions evaluate the chosen
// one and scatter it into the pair's full coordinate vector. Holding the type
// fixed, the dispatched distance is smooth, which is what a Newton step of the
// contact potential differentiates.
//
// Nearly parallel edges and degenerate triangles: the line–line and
// point–plane distances divide by ‖n‖², so the classification never returns
// EA_EB when ‖n‖² <= kParallelSin2 · ‖ea1 − ea0‖² ‖eb1 − eb0‖² (the sine of
// the angle between the edges below 1e-5), nor P_T for a triangle whose
// angle at t0 has such a sine; it returns the closest point–edge or
// point–point pair instead, which is the exact distance for exactly parallel
// edges and within ‖edge‖·1e-5 of it otherwise. The edge–edge mollifier
// (EdgeEdgeMollifier) takes the barrier smoothly to zero well before that.
#pragma once

#include <superdex/core/types.h>

namespace superdex::contact {

template <int n>
using LocalVector = Eigen::Matrix<real, n, 1>;
template <int n>
using LocalMatrix = Eigen::Matrix<real, n, n>;

using Vector2 = LocalVector<2>;
using Matrix2 = LocalMatrix<2>;
using Vector6 = LocalVector<6>;
using Matrix6 = LocalMatrix<6>;
using Vector9 = LocalVector<9>;
using Matrix9 = LocalMatrix<9>;
using Vector12 = LocalVector<12>;
using Matrix12 = LocalMatrix<12>;

/// A scalar function of n coordinates with its gradient and Hessian.
template <int n>
struct ValueGradientHessian {
  real value = 0;
  LocalVector<n> gradient = LocalVector<n>::Zero();
  LocalMatrix<n> hessian = LocalMatrix<n>::Zero();
};

/// The product a·b of two functions of the same coordinates (product rule):
/// ∇(ab) = a∇b + b∇a, ∇²(ab) = a∇²b + b∇²a + ∇a∇bᵀ + ∇b∇aᵀ. Used to apply the
/// edge–edge mollifier to the barrier.
template <int n>
ValueGradientHessian<n> Multiply(ValueGradientHessian<n> const& a,
                                 ValueGradientHessian<n> const& b) {
  ValueGradientHessian<n> r;
  r.value = a.value * b.value;
  r.gradient = a.value * b.gradient + b.value * a.gradient;
  LocalMatrix<n> const cross = a.gradient * b.gradient.transpose();
  r.hessian = a.value * b.hessian + b.value * a.hessian + cross + cross.transpose();
  return r;
}

/// Below this squared sine of the angle between two edges (or between the
/// edges of a triangle at t0) the line–line (point–plane) distance is not
/// used; see the file comment.
inline constexpr real kParallelSin2 = 1e-10;

// ------------------------------------------------------------ point–point

/// ‖p0 − p1‖² [m²].
real PointPointDistance2(Real3 const& p0, Real3 const& p1);
/// Gradient w.r.t. (p0, p1): 2 (p0 − p1; p1 − p0).
Vector6 PointPointDistance2Gradient(Real3 const& p0, Real3 const& p1);
/// Hessian w.r.t. (p0, p1): 2 [I −I; −I I] (constant).
Matrix6 PointPointDistance2Hessian(Real3 const& p0, Real3 const& p1);

// ------------------------------------------------------------- point–line

/// Squared distance from p to the infinite line through e0 and e1 [m²],
/// ‖(e0 − p) × (e1 − p)‖² / ‖e1 − e0‖². Requires e0 ≠ e1.
real PointLineDistance2(Real3 const& p, Real3 const& e0, Real3 const& e1);
/// Gradient w.r.t. (p, e0, e1). Requires e0 ≠ e1.
Vector9 PointLineDistance2Gradient(Real3 const& p, Real3 const& e0, Real3 const& e1);
/// Hessian w.r.t. (p, e0, e1). Requires e0 ≠ e1.
Matrix9 PointLineDistance2Hessian(Real3 const& p, Real3 const& e0, Real3 const& e1);

// ------------------------------------------------------------ point–plane

/// Squared distance from p to the plane of the triangle (t0, t1, t2) [m²],
/// ((p − t0)·n)² / ‖n‖², n = (t1 − t0) × (t2 − t0). Requires n ≠ 0.
real PointPlaneDistance2(Real3 const& p, Real3 const& t0, Real3 const& t1, Real3 const& t2);
/// Gradient w.r.t. (p, t0, t1, t2). Requires n ≠ 0.
Vector12 PointPlaneDistance2Gradient(Real3 const& p, Real3 const& t0, Real3 const& t1,
                                     Real3 const& t2);
/// Hessian w.r.t. (p, t0, t1, t2). Requires n ≠ 0.
Matrix12 PointPlaneDistance2Hessian(Real3 const& p, Real3 const& t0, Real3 const& t1,
                                    Real3 const& t2);

// -------------------------------------------------------------- line–line

/// Squared distance between the infinite lines through (ea0, ea1) and
/// (eb0, eb1) [m²], ((eb0 − ea0)·n)² / ‖n‖², n = (ea1 − ea0) × (eb1 − eb0).
/// Requires non-parallel lines (n ≠ 0).
real LineLineDistance2(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0, Real3 const& eb1);
/// Gradient w.r.t. (ea0, ea1, eb0, eb1). Requires n ≠ 0.
Vector12 LineLineDistance2Gradient(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                                   Real3 const& eb1);
/// Hessian w.r.t. (ea0, ea1, eb0, eb1). Requires n ≠ 0.
Matrix12 LineLineDistance2Hessian(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                                  Real3 const& eb1);

// --------------------------------------------------------- classification

/// The closest feature of a segment (e0, e1) to a point: an end point or the
/// interior (the line).
enum class PointEdgeType { P_E0, P_E1, P_E };

/// The closest features of a point and a closed triangle: a vertex T0..T2,
/// an edge E0 = (t0, t1), E1 = (t1, t2), E2 = (t2, t0), or the interior T.
enum class PointTriangleType { P_T0, P_T1, P_T2, P_E0, P_E1, P_E2, P_T };

/// The closest features of two closed segments a = (ea0, ea1) and
/// b = (eb0, eb1): EAi / EBj an end point, EA / EB the interior of the edge.
enum class EdgeEdgeType {
  EA0_EB0,
  EA0_EB1,
  EA1_EB0,
  EA1_EB1,
  EA_EB0,
  EA_EB1,
  EA0_EB,
  EA1_EB,
  EA_EB
};

/// Which feature of the segment (e0, e1) is closest to p: P_E0 / P_E1 when the
/// projection of p onto the line falls at or beyond that end (or e0 = e1,
/// P_E0), P_E otherwise.
PointEdgeType PointEdgeDistanceType(Real3 const& p, Real3 const& e0, Real3 const& e1);

/// Which feature of the closed triangle is closest to p: P_T when the
/// projection of p onto the plane lies in the closed triangle (and the
/// triangle is not degenerate, see kParallelSin2), otherwise the closest
/// feature of the boundary (a vertex when the closest boundary point is one).
PointTriangleType PointTriangleDistanceType(Real3 const& p, Real3 const& t0, Real3 const& t1,
                                            Real3 const& t2);

/// Which features of the closed segments are closest: EA_EB when the lines'
/// closest points lie on both segments (and the edges are not nearly
/// parallel, see kParallelSin2), otherwise the closest of the four end
/// point–segment pairs.
EdgeEdgeType EdgeEdgeDistanceType(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                                  Real3 const& eb1);

// ------------------------------------------------- dispatch by pair type

/// The squared distance of the pair's features of `type` [m²]: point–point,
/// point–line or point–plane, as a function of the 9 or 12 coordinates.
/// With the type from the classification it is the squared distance between
/// the closed primitives. Value, gradient and Hessian together.
ValueGradientHessian<9> PointEdgeDistance2Derivatives(Real3 const& p, Real3 const& e0,
                                                      Real3 const& e1, PointEdgeType type);
ValueGradientHessian<12> PointTriangleDistance2Derivatives(Real3 const& p, Real3 const& t0,
                                                           Real3 const& t1, Real3 const& t2,
                                                           PointTriangleType type);
ValueGradientHessian<12> EdgeEdgeDistance2Derivatives(Real3 const& ea0, Real3 const& ea1,
                                                      Real3 const& eb0, Real3 const& eb1,
                                                      EdgeEdgeType type);

real PointEdgeDistance2(Real3 const& p, Real3 const& e0, Real3 const& e1, PointEdgeType type);
Vector9 PointEdgeDistance2Gradient(Real3 const& p, Real3 const& e0, Real3 const& e1,
                                   PointEdgeType type);
Matrix9 PointEdgeDistance2Hessian(Real3 const& p, Real3 const& e0, Real3 const& e1,
                                  PointEdgeType type);

real PointTriangleDistance2(Real3 const& p, Real3 const& t0, Real3 const& t1, Real3 const& t2,
                            PointTriangleType type);
Vector12 PointTriangleDistance2Gradient(Real3 const& p, Real3 const& t0, Real3 const& t1,
                                        Real3 const& t2, PointTriangleType type);
Matrix12 PointTriangleDistance2Hessian(Real3 const& p, Real3 const& t0, Real3 const& t1,
                                       Real3 const& t2, PointTriangleType type);

real EdgeEdgeDistance2(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0, Real3 const& eb1,
                       EdgeEdgeType type);
Vector12 EdgeEdgeDistance2Gradient(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                                   Real3 const& eb1, EdgeEdgeType type);
Matrix12 EdgeEdgeDistance2Hessian(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                                  Real3 const& eb1, EdgeEdgeType type);

/// The squared distance between the closed primitives [m²] (classifies, then
/// evaluates).
real PointEdgeDistance2(Real3 const& p, Real3 const& e0, Real3 const& e1);
real PointTriangleDistance2(Real3 const& p, Real3 const& t0, Real3 const& t1, Real3 const& t2);
real EdgeEdgeDistance2(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0, Real3 const& eb1);

/// Whether segment s0–s1 meets triangle t0 t1 t2 (touching counts): the
/// ends on both sides of (or on) the triangle's plane and the segment's line
/// through the triangle (the signs of five orientation volumes; a coplanar
/// segment meets it where their distance is zero).
bool SegmentMeetsTriangle(Real3 const& s0, Real3 const& s1, Real3 const& t0, Real3 const& t1, Real3 const& t2);

// ------------------------------------------------- edge–edge mollifier

/// ε× = 1e-3 ‖ea1 − ea0‖² ‖eb1 − eb0‖² at rest [m⁴]: below c = ε× the
/// edge–edge barrier is mollified.
real EdgeEdgeMollifierThreshold(Real3 const& ea0Rest, Real3 const& ea1Rest, Real3 const& eb0Rest,
                                Real3 const& eb1Rest);

/// c = ‖(ea1 − ea0) × (eb1 − eb0)‖² [m⁴] (zero for parallel edges).
real EdgeEdgeCrossSquaredNorm(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                              Real3 const& eb1);

/// The mollifier m(c) = −c²/ε×² + 2c/ε× for c < ε×, 1 otherwise
/// (dimensionless, C¹ at c = ε×: m = 1, m′ = 0 there; m = 0 for parallel
/// edges). `threshold` is ε× from EdgeEdgeMollifierThreshold; with
/// threshold <= 0 (a degenerate rest edge) m = 1.
real EdgeEdgeMollifier(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0, Real3 const& eb1,
                       real threshold);
/// m with its gradient and Hessian w.r.t. (ea0, ea1, eb0, eb1):
/// ∇m = m′(c)∇c, ∇²m = m″(c)∇c∇cᵀ + m′(c)∇²c (zero for c >= ε×).
ValueGradientHessian<12> EdgeEdgeMollifierDerivatives(Real3 const& ea0, Real3 const& ea1,
                                                      Real3 const& eb0, Real3 const& eb1,
                                                      real threshold);
Vector12 EdgeEdgeMollifierGradient(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                                   Real3 const& eb1, real threshold);
Matrix12 EdgeEdgeMollifierHessian(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                                  Real3 const& eb1, real threshold);

// ------------------------------------------- closest points and tangents

/// Orthonormal columns spanning the tangent plane of a contact (3×2).
using TangentBasis = Eigen::Matrix<real, 3, 2>;

/// The tangent frame of a contact for friction: an orthonormal basis T of
/// the plane orthogonal to the contact normal, and the weights Γ (3 × n)
/// that map the pair's displacement Δx (n = 6, 9 or 12, the pair's
/// coordinate order) to the relative displacement of the two closest points,
/// Δ(first primitive's point) − Δ(second primitive's point). The relative
/// tangential displacement is u = Tᵀ Γ Δx ∈ R² [m]. Γ x (applied to positions)
/// is the vector between the two closest points, orthogonal to T.
template <int n>
struct TangentFrame {
  TangentBasis basis = TangentBasis::Zero();
  Eigen::Matrix<real, 3, n> weights = Eigen::Matrix<real, 3, n>::Zero();
};

/// A basis orthogonal to p0 − p1 (any, deterministic, when p0 = p1).
TangentBasis PointPointTangentBasis(Real3 const& p0, Real3 const& p1);
/// Γ = [I, −I]: Δp0 − Δp1.
Eigen::Matrix<real, 3, 6> PointPointDisplacementWeights();

/// α with e0 + α (e1 − e0) the closest point of the line to p (unclamped;
/// 0 when e0 = e1).
real PointEdgeClosestPointParameter(Real3 const& p, Real3 const& e0, Real3 const& e1);
/// Basis (ê, n̂ × ê): ê the edge direction, n̂ the direction from the line to
/// p; orthogonal to the point–line normal. Any basis containing ê when p is
/// on the line, PointPointTangentBasis(p, e0) when e0 = e1.
TangentBasis PointEdgeTangentBasis(Real3 const& p, Real3 const& e0, Real3 const& e1);
/// Γ = [I, −(1 − α) I, −α I]: Δp − ((1 − α)Δe0 + αΔe1).
Eigen::Matrix<real, 3, 9> PointEdgeDisplacementWeights(real alpha);

/// (β1, β2) with t0 + β1 (t1 − t0) + β2 (t2 − t0) the orthogonal projection
/// of p onto the triangle's plane (unclamped). For a degenerate triangle
/// (see kParallelSin2) the coordinates of the closest point of its boundary.
Vector2 PointTriangleClosestPointCoordinates(Real3 const& p, Real3 const& t0, Real3 const& t1,
                                             Real3 const& t2);
/// Basis (û, n̂ × û) of the triangle's plane, u = t1 − t0, n̂ the unit normal.
/// A basis containing û (or any) for a degenerate triangle.
TangentBasis PointTriangleTangentBasis(Real3 const& t0, Real3 const& t1, Real3 const& t2);
/// Γ = [I, −(1 − β1 − β2) I, −β1 I, −β2 I]: Δp − ((1−β1−β2)Δt0 + β1Δt1 + β2Δt2).
Eigen::Matrix<real, 3, 12> PointTriangleDisplacementWeights(Vector2 const& beta);

/// (α, β) with ea0 + α (ea1 − ea0) and eb0 + β (eb1 − eb0) the closest
/// points of the two lines (unclamped). For nearly parallel edges (see
/// kParallelSin2) α = 0 and β the parameter of ea0's projection onto line b.
Vector2 EdgeEdgeClosestPointParameters(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                                       Real3 const& eb1);
/// Basis (â, n̂ × â): â edge a's direction, n̂ the common normal
/// (ea1 − ea0) × (eb1 − eb0) normalized. A basis containing â (or any) for
/// parallel or degenerate edges.
TangentBasis EdgeEdgeTangentBasis(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                                  Real3 const& eb1);
/// Γ = [(1 − α) I, α I, −(1 − β) I, −β I] for alphaBeta = (α, β):
/// ((1 − α)Δea0 + αΔea1) − ((1 − β)Δeb0 + βΔeb1).
Eigen::Matrix<real, 3, 12> EdgeEdgeDisplacementWeights(Vector2 const& alphaBeta);

/// The tangent frame of a pair for its `type`: the basis and weights of the
/// features that are closest (a point–edge type of a triangle uses the
/// point–edge basis and puts the edge's coordinates (α on the edge) into the
/// triangle's β; a vertex type the point–point basis).
TangentFrame<9> PointEdgeTangentFrame(Real3 const& p, Real3 const& e0, Real3 const& e1,
                                      PointEdgeType type);
TangentFrame<12> PointTriangleTangentFrame(Real3 const& p, Real3 const& t0, Real3 const& t1,
                                           Real3 const& t2, PointTriangleType type);
TangentFrame<12> EdgeEdgeTangentFrame(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0,
                                      Real3 const& eb1, EdgeEdgeType type);

}  // namespace superdex::contact

// Continuous collision detection (CCD) along linear trajectories, for the
// line search of the contact Newton solver: how far along a step the
// primitives of a contact pair can move and stay apart.
//
// Every vertex moves linearly, x(t) = x⁰ + t·Δx, and the pair's distance is
// d(t), the exact unsigned distance between the closed primitives (a point,
// a segment with its endpoints, a triangle with its edges and vertices). With
// the minimum separation ξ (the thickness; for rods and points with radii,
// the sum of the radii) the gap is g(t) = d(t) − ξ, and with the rescaling
// s ∈ (0, 1) the target gap is g* = (1 − s)·g(0). Every function returns a
// time t* ∈ [0, tMax] such that
//
//   g(t) ≥ g*  for every t ∈ [0, t*],
//
// so the pair keeps at least the fraction 1 − s of its start gap (10 % by
// default) and is never closer than ξ on the step to t*. If the pair starts
// at or below the thickness (g(0) ≤ 0), every function returns 0.
//
// The primitive pairs use additive CCD (Li, Kaufman, Jiang, "Codimensional
// Incremental Potential Contact", 2021): the mean displacement of the
// pair's vertices is subtracted (distances do not change under a common
// translation), and with L = lₐ + l_b, l the largest remaining displacement
// ‖Δxᵢ − Δx̄‖ of each side, d is L-Lipschitz in t: any point of a primitive
// is a convex combination of its vertices, so it moves by at most l·τ in a
// time τ. Conservative advancement from t with the exact distance at t,
//
//   t ← t + (g(t) − g*)/L,
//
// can therefore not take the gap below g*. The iteration stops once
// g(t) − g* ≤ η·(g(0) − g*) (η = kCcdStopFraction) and returns that t; it
// returns tMax as soon as a step reaches it. So t* is also never below the
// first time the gap falls to g* + η·s·g(0) (an advanced time before it
// cannot stop, and the advances cannot pass it without stopping unless the
// gap rises again), and is tMax when the gap stays above that level on
// [0, tMax]; unless the cap below is reached. Each step before the stop is
// longer than η·s·g(0)/L, so at most L·tMax/(η·s·g(0)) + 1 distance
// evaluations are made; the cap maxIterations is reached only when the
// relative motion is that much larger than the start gap (a fast slide at a
// small gap), and then the last advanced time is returned, which keeps the
// guarantee above but may be far smaller than the time of impact. A pair
// without relative motion (L = 0) returns tMax.
//
// The analytic obstacles (a plane, a sphere) have closed forms and return
// exactly the first time the gap reaches g* (or tMax if it does not before).
//
// Units: positions and displacements in m, thickness and radii in m, times
// in fractions of the step (t = 1 is the full displacement). Inputs are
// assumed finite, with thickness ≥ 0, tMax ≥ 0 (tMax may exceed 1: the
// trajectories extend linearly), rescale ∈ (0, 1) and maxIterations ≥ 1.
// The result is in [0, tMax] whatever the arguments (0 when tMax is not
// positive), rescale is clamped to [0, 1], and maxIterations < 1 advances
// nothing (0, or tMax without relative motion). The guarantees hold in exact
// arithmetic; in floating point they hold to the round-off of evaluating
// the distances, a few ulps of the positions, far inside the kept gap g*
// unless g(0) itself is at round-off level.
#pragma once

#include <superdex/core/types.h>

namespace superdex::contact {

/// s: the default share of the start gap a step may close (10 % is kept).
inline constexpr real kCcdRescale = 0.9;
/// η: additive CCD stops once the gap above the target g* is at most this
/// fraction of its start value, s·g(0).
inline constexpr real kCcdStopFraction = 0.05;
/// The default cap on distance evaluations of one additive CCD query.
inline constexpr int kCcdMaxIterations = 10000;

/// A point p against a triangle (t0, t1, t2), the triangle closed (the point
/// may come closest to its interior, an edge or a vertex). Displacements dp,
/// dt0, dt1, dt2 over the step. Returns t* as in the file comment.
real PointTriangleCcd(Real3 const& p, Real3 const& t0, Real3 const& t1, Real3 const& t2,
                      Real3 const& dp, Real3 const& dt0, Real3 const& dt1, Real3 const& dt2,
                      real thickness, real tMax, real rescale = kCcdRescale,
                      int maxIterations = kCcdMaxIterations);

/// Segment (ea0, ea1) against segment (eb0, eb1), both closed (endpoints and
/// parallel segments included). Returns t* as in the file comment.
real EdgeEdgeCcd(Real3 const& ea0, Real3 const& ea1, Real3 const& eb0, Real3 const& eb1,
                 Real3 const& dea0, Real3 const& dea1, Real3 const& deb0, Real3 const& deb1,
                 real thickness, real tMax, real rescale = kCcdRescale,
                 int maxIterations = kCcdMaxIterations);

/// A point p against the closed segment (e0, e1): a rod node against a rod
/// segment, thickness the sum of their radii. Returns t* as in the file
/// comment.
real PointEdgeCcd(Real3 const& p, Real3 const& e0, Real3 const& e1, Real3 const& dp,
                  Real3 const& de0, Real3 const& de1, real thickness, real tMax,
                  real rescale = kCcdRescale, int maxIterations = kCcdMaxIterations);

/// Point a against point b: two particles or rod nodes, thickness the sum of
/// their radii. Returns t* as in the file comment.
real PointPointCcd(Real3 const& a, Real3 const& b, Real3 const& da, Real3 const& db,
                   real thickness, real tMax, real rescale = kCcdRescale,
                   int maxIterations = kCcdMaxIterations);

/// A point p of radius r against the half-space n·x ≥ c whose offset moves
/// linearly, c(t) = c + t·dc (a static plane has dc = 0; the normal does not
/// turn). n need not be unit but must be non-zero. The gap is
/// g(t) = (n·p(t) − c(t))/‖n‖ − r, linear in t. Returns 0 if g(0) ≤ 0; else
/// the time g reaches (1 − rescale)·g(0), s·g(0)/(−ġ), when the gap closes
/// (ġ < 0) and that time is below tMax; else tMax.
real PointPlaneCcd(Real3 const& p, Real3 const& dp, real radius, Real3 const& normal,
                   real offset, real offsetDisplacement, real tMax, real rescale = kCcdRescale);

/// A point p of radius r outside a sphere of radius R whose centre c moves
/// linearly (dc = 0 for a static sphere). The gap is
/// g(t) = ‖p(t) − c(t)‖ − r − R. Returns 0 if g(0) ≤ 0; else the first root
/// of the quadratic ‖p(t) − c(t)‖² = (r + R + (1 − rescale)·g(0))² when it
/// is below tMax (the first time g reaches (1 − rescale)·g(0)); else tMax.
real PointSphereCcd(Real3 const& p, Real3 const& dp, real radius, Real3 const& center,
                    Real3 const& dCenter, real sphereRadius, real tMax,
                    real rescale = kCcdRescale);

}  // namespace superdex::contact

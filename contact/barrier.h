// The contact barrier and the friction ramp of incremental potential contact
// (Li et al. 2020, "Incremental Potential Contact"; Li et al. 2021,
// "Codimensional Incremental Potential Contact").
//
// Barrier. In dimensionless form
//   b(s) = −(s − 1)² ln s   for 0 < s < 1,   0 for s >= 1,   +∞ for s <= 0,
//   b′(s) = −2(s − 1) ln s − (s − 1)²/s,
//   b″(s) = −2 ln s + (1 − s)(1 + 3s)/s².
// b, b′ and b″ all vanish at s = 1, so b is C² there (b‴ jumps from −6 to 0:
// not C³). On (0, 1) b > 0, b′ < 0, b″ > 0; as s → 0⁺, b ~ −ln s → +∞.
// The contact energy of one pair is
//   E = κ w d̂ b(d/d̂),   d = sqrt(d²) − thickness,
// κ [Pa] the contact stiffness, w [m²] the pair's area weight, d̂ [m] the
// activation distance, thickness [m] >= 0 the sum of the two primitives'
// radii (codimensional IPC); E is in J. (IPC's b(d, d̂) = −(d − d̂)² ln(d/d̂)
// is d̂² b(d/d̂).)
//
// Friction. The ramp of the library's compliant potential (the same as
// constraint saturation), with ḡ [m] > 0 the slip distance at which the
// friction force reaches μλ:
//   ρ(x) = x²/ḡ − x³/(3ḡ²)   for 0 <= x < ḡ,   x − ḡ/3 for x >= ḡ,
//   ρ′(x) = 2x/ḡ − x²/ḡ² ∈ [0, 1] below ḡ, 1 beyond;   ρ″(x) = 2/ḡ − 2x/ḡ² below, 0 beyond.
// ρ is C² at ḡ (ρ = 2ḡ/3, ρ′ = 1, ρ″ = 0 from both sides). The friction
// energy of one contact with lagged normal force λ >= 0 [N], coefficient μ,
// lagged tangent frame (T, Γ) (contact/distance.h) is
//   D(Δx) = μλ ρ(‖u‖),   u = Tᵀ Γ Δx ∈ R² [m],   Δx = x − x_anchor,
//   ∇_u D = μλ (ρ′/‖u‖) u,
//   ∇_u² D = μλ [ρ″ ûûᵀ + (ρ′/‖u‖)(I − ûûᵀ)],   û = u/‖u‖,
// PSD since ρ″ >= 0 and ρ′/x > 0, and regular at u = 0, where it is
// (2μλ/ḡ) I. The friction force on the pair is −Γᵀ T ∇_u D; its magnitude
// ‖∇_u D‖ = μλ ρ′ never exceeds μλ (Coulomb).
#pragma once

#include <superdex/contact/distance.h>
#include <superdex/core/types.h>

namespace superdex::contact {

// ----------------------------------------------------------------- barrier

/// b(s) (dimensionless); +∞ for s <= 0, 0 for s >= 1.
real Barrier(real s);
/// b′(s); −∞ for s <= 0 (the limit s → 0⁺), 0 for s >= 1.
real BarrierDerivative(real s);
/// b″(s); +∞ for s <= 0 (the limit s → 0⁺), 0 for s >= 1.
real BarrierSecondDerivative(real s);

/// Parameters of one pair's barrier energy E = κ w d̂ b((sqrt(d²) − thickness)/d̂).
struct BarrierParams {
  real thickness = 0;           ///< sum of the primitives' radii [m], >= 0
  real activationDistance = 0;  ///< d̂ [m], > 0: no energy at d >= d̂
  real stiffnessArea = 0;       ///< κ w: stiffness [Pa] times area weight [m²], so [N/m], >= 0
};

/// What BarrierEnergy returns as the Hessian. With q = d² and
/// E(q) = κ w d̂ b((sqrt(q) − thickness)/d̂),
///   ∇E = φ′ ∇q,   ∇²E = φ″ ∇q∇qᵀ + φ′ ∇²q,
///   φ′ = κ w b′(s)/(2 sqrt(q)) <= 0,   φ″ = κ w [b″(s)/(4 d̂ q) − b′(s)/(4 q^{3/2})] >= 0.
enum class BarrierHessian {
  Exact,      ///< φ″ ∇q∇qᵀ + φ′ ∇²q, which may be indefinite (φ′ <= 0)
  Projected,  ///< Exact with its negative eigenvalues clamped to 0 (SelfAdjointEigenSolver), as IPC
              ///< does
  GaussNewton,  ///< φ″ ∇q∇qᵀ only: the curvature of d² dropped; PSD by construction, no eigensolver
};

/// E, ∇E and ∇²E of one pair, given its squared distance q = d² [m²] with
/// gradient and Hessian w.r.t. the pair's n coordinates (n = 6, 9 or 12;
/// other sizes are not instantiated). Zero (value, gradient and Hessian)
/// when d >= d̂. When d <= 0 (penetration of the thickness) the energy is +∞
/// and the gradient and Hessian are zero: the caller's line search must keep
/// d > 0. Requires d̂ > 0.
template <int n>
ValueGradientHessian<n> BarrierEnergy(ValueGradientHessian<n> const& distance2,
                                      BarrierParams const& params, BarrierHessian hessianForm);

/// The symmetric `a` with its negative eigenvalues clamped to 0
/// (Eigen::SelfAdjointEigenSolver); `a` itself when none is negative.
/// Instantiated for n = 2, 6, 9 and 12.
template <int n>
LocalMatrix<n> ProjectToPsd(LocalMatrix<n> const& a);

// --------------------------------------------------------- friction ramp

/// ρ(x) [m] for x >= 0 and ḡ = saturation > 0.
real FrictionRamp(real x, real saturation);
/// ρ′(x) ∈ [0, 1] (dimensionless).
real FrictionRampDerivative(real x, real saturation);
/// ρ″(x) [1/m], >= 0.
real FrictionRampSecondDerivative(real x, real saturation);
/// ρ′(x)/x [1/m]: 2/ḡ − x/ḡ² below ḡ (2/ḡ at x = 0), 1/x beyond.
real FrictionRampDerivativeOverX(real x, real saturation);

/// The friction energy of one contact as a function of the relative
/// tangential displacement u [m]: D [J], ∇_u D [N] and ∇_u² D [N/m] (2×2, PSD).
struct TangentialFriction {
  real energy = 0;
  Vector2 gradient = Vector2::Zero();
  Matrix2 hessian = Matrix2::Zero();
};

/// D = μλ ρ(‖u‖) with `muLambda` = μλ [N] >= 0 and ḡ = saturation [m] > 0,
/// its gradient and Hessian in u (see the file comment; regular at u = 0).
TangentialFriction EvaluateTangentialFriction(Vector2 const& u, real muLambda, real saturation);

/// The friction energy in the pair's n coordinates through u = Tᵀ Γ Δx:
/// gradient Γᵀ T ∇_u D, Hessian Γᵀ T ∇_u² D Tᵀ Γ. Instantiated for n = 6, 9, 12.
template <int n>
ValueGradientHessian<n> MapTangentialFriction(TangentialFriction const& friction,
                                              TangentFrame<n> const& frame);

/// D(Δx) = μλ ρ(‖Tᵀ Γ Δx‖) with its gradient and Hessian w.r.t. the pair's
/// n coordinates; `displacement` = x − x_anchor in the pair's coordinate
/// order. Instantiated for n = 6, 9, 12.
template <int n>
ValueGradientHessian<n> FrictionEnergy(LocalVector<n> const& displacement,
                                       TangentFrame<n> const& frame, real muLambda,
                                       real saturation);

}  // namespace superdex::contact

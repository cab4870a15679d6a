// The compliant potential shared by every constraint type (constraints.md,
// "Mathematical formulation"). A type supplies g and J only; stiffness k,
// damping d, saturation ḡ and the range rule live here, once.
//
//   Φᶜ = U(‖g‖) + d/(2Δtᵢ) ‖Δg‖²,   Δg = g(q, p̂) − g(qᵢ⁰, p̂ᵢ⁰)
//   U  = k/2 ‖g‖²                        (saturation disabled, ḡ <= 0)
//   U  = k ḡ ρ(‖g‖),  ρ(x) = x²/ḡ − x³/(3ḡ²) for x < ḡ,  x − ḡ/3 for x >= ḡ
//   rᶜ = Jᵀ (κ g + d/Δtᵢ Δg),   κ = k  or  k ḡ ρ'(‖g‖)/‖g‖
//   Kᶜ ≈ (κ + d/Δtᵢ) JᵀJ        (Gauss–Newton, PSD)
//
// ρ'(x)/x = 2/ḡ − x/ḡ² below ḡ (regular at x = 0: κ → 2k) and 1/x above, so
// κ = k(2 − x/ḡ) for x < ḡ and k ḡ/x for x >= ḡ; the elastic force magnitude
// κ‖g‖ = k ḡ ρ'(‖g‖) never exceeds k ḡ.
#pragma once

#include <superdex/core/types.h>

namespace superdex::internal {

struct CompliantParams {
  real stiffness = 0;    ///< k >= 0
  real damping = 0;      ///< d >= 0
  real saturation = -1;  ///< ḡ; <= 0 disables saturation

  bool IsSaturated() const { return saturation > 0; }
};

/// U(x) at x = ‖g‖.
real CompliantElasticEnergy(CompliantParams const& p, real x);
/// κ(x) at x = ‖g‖ (regular at x = 0).
real CompliantKappa(CompliantParams const& p, real x);

/// The near-rigid cap (NewtonParams::nearRigidBeta; after the near-rigid
/// regime of Drake's SAP, Castro et al. 2022, "An Unconstrained Convex
/// Formulation of Compliant Contact", §V). A constraint whose Gauss–Newton
/// scale s = k + d/h exceeds
///
///   s_max = 4π² / (β² h² w)
///
/// (w the constraint's inverse effective mass, an estimate of the largest
/// diagonal entry of the Delassus operator J M⁻¹ Jᵀ) would oscillate with a
/// period below β h, which the stage cannot resolve and which makes the
/// Newton Hessian ill-conditioned. Its stiffness and damping are scaled by
/// c = s_max / s, which keeps the ratio d/k (SAP keeps the relaxation time τ
/// and clamps the regularization R = 1/(h²(k + d/h)) from below by
/// β² w/(4π²): the same thing); a saturated constraint's ḡ becomes ḡ/c, which
/// keeps its force cap k ḡ. With d = 0 this is k_eff = min(k, 4π²/(β² h² w)).
/// Returns `p` itself when β <= 0, w <= 0 or s <= s_max; `capped` says
/// whether the cap applied.
CompliantParams NearRigidParams(CompliantParams const& p, real h, real beta, real w, bool& capped);

/// A range constraint is inactive, and contributes nothing, when every
/// component of g is zero both now and at the stage start.
bool IsRangeInactive(Eigen::Ref<VectorX const> const& g, Eigen::Ref<VectorX const> const& gStart);

/// Φᶜ for the given g, stage-start g⁰ and stage duration h.
real CompliantEnergy(CompliantParams const& p, Eigen::Ref<VectorX const> const& g,
                     Eigen::Ref<VectorX const> const& gStart, real h);

/// The generalized force coefficients f = κ g + d/h (g − g⁰) (so rᶜ = Jᵀ f)
/// into `f`, and returns the Gauss–Newton scale κ + d/h.
real CompliantForceCoefficients(CompliantParams const& p, Eigen::Ref<VectorX const> const& g,
                                Eigen::Ref<VectorX const> const& gStart, real h,
                                Eigen::Ref<VectorX> f);

}  // namespace superdex::internal

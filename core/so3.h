// SO(3) maps used by every rotational quantity.
//
// Conventions (Sola et al., "A micro Lie theory for state estimation in
// robotics", 2018):
//   Exp(φ)                  rotation by angle |φ| about φ/|φ|
//   Log(R)                  its inverse, |Log(R)| ∈ [0, π]
//   Exp(φ + δ) ≈ Exp(J_l(φ) δ) Exp(φ) ≈ Exp(φ) Exp(J_r(φ) δ)
//   Log(Exp(δ) R) ≈ Log(R) + J_l⁻¹(Log R) δ      (world / left increment)
//   Log(R Exp(δ)) ≈ Log(R) + J_r⁻¹(Log R) δ      (body / right increment)
// Rigid-body rotations are updated with world-frame increments,
// R ← Exp(δθ) R, so constraint Jacobians use the left forms.
//
// Every function is accurate near φ = 0 (series expansions) and stays
// finite up to |φ| = π (the inverse Jacobians use cot(θ/2), which is regular
// at π).
#pragma once

#include <superdex/core/types.h>

namespace superdex {

/// The skew-symmetric cross-product matrix: Hat(a) b = a × b.
Real33 Hat(Real3 const& a);

/// Unit quaternion of the rotation vector φ.
Quat Exp(Real3 const& phi);
/// Rotation matrix of the rotation vector φ.
Real33 ExpMatrix(Real3 const& phi);

/// Rotation vector of a unit quaternion (either sign), |result| ∈ [0, π].
Real3 Log(Quat const& q);
/// Rotation vector of a rotation matrix, |result| ∈ [0, π].
Real3 Log(Real33 const& rotation);

Real33 LeftJacobian(Real3 const& phi);
Real33 LeftJacobianInverse(Real3 const& phi);
/// γ(θ) of J_l⁻¹(φ) = I − ½ Hat(φ) + γ Hat(φ)²: 1/θ² − cot(θ/2)/(2θ),
/// regular at θ = 0 (→ 1/12) and at θ = π (→ 1/π²).
real LeftJacobianInverseCoefficient(real theta);
/// γ′(θ)/θ (→ 1/360 at θ = 0): D(J_l⁻¹)(φ)[b] has the term (γ′/θ)(φ·b) Hat(φ)².
real LeftJacobianInverseCoefficientRate(real theta);
Real33 RightJacobian(Real3 const& phi);
Real33 RightJacobianInverse(Real3 const& phi);

}  // namespace superdex

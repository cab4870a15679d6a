// Internal kinematics shared by the rotational constraint types.
//
// Every rotational g of constraints.md has the form
//
//   φ = Log(Lᵀ Q)
//
// with L and Q products of body rotations and constant frames. A world-frame
// increment δ of a rotation that multiplies Q from the left (Q ← Exp(δ) Q)
// gives dφ/dδ = J_l⁻¹(φ) Lᵀ; the same increment of a rotation multiplying L
// from the left gives −J_l⁻¹(φ) Lᵀ.
//
// Curvature (the geometric-stiffness term, constraint.h): for weights w,
// RotationResidualCurvature gives the 6×6 Hessian of wᵀφ w.r.t. (δL, δQ),
// L ← Exp(δL) L, Q ← Exp(δQ) Q, by second-order forward differentiation
// (core/so3_jet.h). A point carried by a rotation, Exp(δ) a, has
// ∂²(wᵀ Exp(δ) a)/∂δ² = ½(w aᵀ + a wᵀ) − (w·a) I at δ = 0 (from
// Exp(δ) a = a + δ × a + ½ δ × (δ × a) + O(δ³)).
//
// Range types measure the one-sided violation of each component against
// bounds l ≤ x ≤ u (constraints.md): g = max(x − u, l − x, 0), whose
// derivative is +dx above u, −dx below l and 0 inside.
#pragma once

#include <superdex/core/so3.h>
#include <superdex/core/so3_jet.h>
#include <superdex/core/types.h>

namespace superdex::internal {

struct RotationResidual {
  Real3 value;         ///< φ = Log(Lᵀ Q)
  Real33 derivativeQ;  ///< dφ/dδ for Q ← Exp(δ) Q; for L ← Exp(δ) L it is −derivativeQ
};

inline RotationResidual EvaluateRotationResidual(Quat const& left, Quat const& right) {
  RotationResidual r;
  r.value = Log(left.conjugate() * right);
  r.derivativeQ = LeftJacobianInverse(r.value) * left.conjugate().toRotationMatrix();
  return r;
}

using Matrix6 = Eigen::Matrix<real, 6, 6>;

/// (Exp(δL) L)ᵀ = Lᵀ Exp(−δL) as jets, δL the variables first … first + 2.
template <int N>
JetMatrix3<N> TurnedLeftTransposed(Quat const& left, int first) {
  JetVector3<N> minusIncrement = JetIncrement<N>(first);
  for (Jet<N>& u : minusIncrement) u = -u;
  return Multiply(left.conjugate().toRotationMatrix(), ExpSecondOrder(minusIncrement));
}

/// Hessian of wᵀ Log(Lᵀ Q) w.r.t. (δL, δQ) at zero, δL first.
Matrix6 RotationResidualCurvature(Quat const& left, Quat const& right, Real3 const& weights);

/// ∂²(wᵀ Exp(δ) a)/∂δ² at δ = 0, for a world vector a carried by a rotation.
inline Real33 RotatedVectorCurvature(Real3 const& weights, Real3 const& arm) {
  Real33 const outer = weights * arm.transpose();
  return 0.5 * (outer + outer.transpose()) - weights.dot(arm) * Real33::Identity();
}

/// g = max(x − u, l − x, 0) and its derivative dg/dx ∈ {+1, −1, 0}.
inline real OneSidedViolation(real x, real lower, real upper, real& slope) {
  if (x > upper) {
    slope = 1;
    return x - upper;
  }
  if (x < lower) {
    slope = -1;
    return lower - x;
  }
  slope = 0;
  return 0;
}

}  // namespace superdex::internal

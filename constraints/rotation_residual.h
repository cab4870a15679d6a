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
// Range types measure the one-sided violation of each component against
// bounds l ≤ x ≤ u (constraints.md): g = max(x − u, l − x, 0), whose
// derivative is +dx above u, −dx below l and 0 inside.
#pragma once

#include <superdex/core/so3.h>
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

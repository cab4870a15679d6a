#include <superdex/constraints/rotation_residual.h>

namespace superdex::internal {

Matrix6 RotationResidualCurvature(Quat const& left, Quat const& right, Real3 const& weights) {
  // φ(δL, δQ) = Log(Lᵀ Exp(−δL) Exp(δQ) Q), as (Exp(δL) L)ᵀ = Lᵀ Exp(δL)ᵀ
  using J = Jet<6>;
  JetMatrix3<6> const m =
      Multiply(Multiply(TurnedLeftTransposed<6>(left, 0), ExpSecondOrder(JetIncrement<6>(3))), right.toRotationMatrix());
  JetVector3<6> const phi = LogJet(m);
  J const contracted = weights[0] * phi[0] + weights[1] * phi[1] + weights[2] * phi[2];
  return contracted.hessian;
}

}  // namespace superdex::internal

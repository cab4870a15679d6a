// RigidPivotPosition — pins a point of a rigid body to a kinematic target.
//
//   g = T(r) − p̂ = t + R r − p̂                                  m = 3, n = 6
//   J = [ I, −Hat(R r) ]
// Target p̂ (world, m) set with SetTargetPosition; moving it between steps
// produces a damping force unless UpdateOldTarget is called (teleport).
#pragma once

#include <superdex/constraints/constraint.h>
#include <superdex/core/handle.h>

namespace superdex {


struct RigidPivotPositionConstraintParams {
  ActorHandle actor;                 ///< a rigid actor, or an articulated actor with `link`
  int link = -1;                     ///< the articulated actor's link acting as the body (−1: a rigid actor)
  Real3 localPos = Real3::Zero();    ///< pivot r in the body frame [m]
  Real3 position = Real3::Zero();    ///< target p̂, world [m]
  real stiffness = 0;                ///< k >= 0 [N/m]
  real damping = 0;                  ///< d >= 0 [N·s/m]
  real saturation = -1;              ///< ḡ [m]; <= 0 disables
};

class RigidPivotPositionConstraint final : public Constraint {
 public:
  RigidPivotPositionConstraint(internal::RigidBodySlot body, RigidPivotPositionConstraintParams const& params);

  Real3 const& GetLocalPos() const { return localPos_; }
  Real3 GetTargetPosition() const { return TargetPosition(GetTarget()); }

 private:
  void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                  Eigen::Ref<MatrixX> jacobian) const override;
  void DoAddCurvature(Span<real const> target, Eigen::Ref<VectorX const> const& weights,
                      Eigen::Ref<MatrixX> hessian) const override;

  Real3 localPos_;
};

}  // namespace superdex

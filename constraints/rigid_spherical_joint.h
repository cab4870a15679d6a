// RigidSphericalJoint — ball-and-socket between two rigid bodies.
//
//   g = T_A(r_A) − T_B(r_B) = t_A + R_A r_A − t_B − R_B r_B      m = 3, n = 12
//   J = [ I, −Hat(R_A r_A), −I, Hat(R_B r_B) ]
// (columns: A translation, A rotation increment, B translation, B rotation
// increment; R ← Exp(δθ) R). Units: g in m, stiffness N/m, damping N·s/m.
#pragma once

#include <superdex/constraints/constraint.h>
#include <superdex/core/handle.h>

namespace superdex {


struct RigidSphericalJointConstraintParams {
  ActorHandle actorA;                 ///< a rigid actor, or an articulated actor with `linkA`
  ActorHandle actorB;                 ///< a different rigid actor, or an articulated actor with `linkB`
  int linkA = -1;                     ///< the link acting as body A (−1: a rigid actor)
  int linkB = -1;                     ///< the link acting as body B (−1: a rigid actor)
  Real3 localPosA = Real3::Zero();    ///< pivot r_A in A's body frame [m]
  Real3 localPosB = Real3::Zero();    ///< pivot r_B in B's body frame [m]
  real stiffness = 0;                 ///< k >= 0 [N/m]
  real damping = 0;                   ///< d >= 0 [N·s/m]
  real saturation = -1;               ///< ḡ [m]; <= 0 disables
};

class RigidSphericalJointConstraint final : public Constraint {
 public:
  RigidSphericalJointConstraint(internal::RigidBodySlot bodyA, internal::RigidBodySlot bodyB,
                                RigidSphericalJointConstraintParams const& params);

  Real3 const& GetLocalPosA() const { return localPosA_; }
  Real3 const& GetLocalPosB() const { return localPosB_; }

 private:
  void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                  Eigen::Ref<MatrixX> jacobian) const override;
  void DoAddCurvature(Span<real const> target, Eigen::Ref<VectorX const> const& weights,
                      Eigen::Ref<MatrixX> hessian) const override;

  Real3 localPosA_, localPosB_;
};

}  // namespace superdex

// DeformableNodeToRigid — attaches a deformable node to a point of a rigid
// body (a soft body hanging from a handle, a rod end on a body).
//
//   g = T_R(r) − T_D(X + u) = t_R + R_R r − T_D(X + u)             m = 3, n = 9
//   J = [ −R_TD, I, −Hat(R_R r) ]
// Columns: the node's 3 DoFs (actor 0, the deformable one), then the rigid
// body's translation and rotation increment (actor 1). By default
// (fixToDeformablePos) the rigid-frame pivot r is computed at creation as
// R_Rᵀ(T_D(X + u) − t_R), so the constraint starts at zero deviation;
// otherwise r = localPos. Units: m, N/m, N·s/m.
#pragma once

#include <superdex/constraints/constraint.h>

namespace superdex {

class NodalActor;

struct DeformableNodeToRigidConstraintParams {
  ActorHandle deformableActor;        ///< a deformable actor
  ActorHandle rigidActor;             ///< a rigid actor, or an articulated actor with `rigidLink`
  int rigidLink = -1;                 ///< the link acting as the rigid body (−1: a rigid actor)
  int deformableNodeIndex = 0;        ///< node of the deformable actor
  bool fixToDeformablePos = true;     ///< r from the node's position at creation
  Real3 localPos = Real3::Zero();     ///< r in the rigid body frame when !fixToDeformablePos [m]
  real stiffness = 0;                 ///< k >= 0 [N/m]
  real damping = 0;                   ///< d >= 0 [N·s/m]
  real saturation = -1;               ///< ḡ [m]; <= 0 disables
};

class DeformableNodeToRigidConstraint final : public Constraint {
 public:
  DeformableNodeToRigidConstraint(NodalActor* deformable, internal::RigidBodySlot rigid,
                                  DeformableNodeToRigidConstraintParams const& params);
  /// r, the pivot in the rigid body's frame.
  Real3 const& GetLocalPos() const { return localPos_; }

 private:
  void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                  Eigen::Ref<MatrixX> jacobian) const override;
  void DoAddCurvature(Span<real const> target, Eigen::Ref<VectorX const> const& weights,
                      Eigen::Ref<MatrixX> hessian) const override;

  NodalActor* deformable_;
  int node_;
  Real3 localPos_;
};

}  // namespace superdex

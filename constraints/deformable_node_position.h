// DeformableNodePosition — pins a node of a deformable actor to a target
// (boundary conditions: a shell corner, the base of a soft body).
//
//   g = T(X + u) − p̂                                             m = 3, n = 3
//   J = R_T      (columns: the node's 3 displacement DoFs)
// Target p̂ (world, m) set with SetTargetPosition. Units: m, N/m, N·s/m.
#pragma once

#include <superdex/constraints/constraint.h>

namespace superdex {

class NodalActor;

struct DeformableNodePositionConstraintParams {
  ActorHandle actor;                ///< a deformable actor
  int nodeIndex = 0;                ///< in [0, number of nodes)
  Real3 position = Real3::Zero();   ///< target p̂, world [m]
  real stiffness = 0;               ///< k >= 0 [N/m]
  real damping = 0;                 ///< d >= 0 [N·s/m]
  real saturation = -1;             ///< ḡ [m]; <= 0 disables
};

class DeformableNodePositionConstraint final : public Constraint {
 public:
  DeformableNodePositionConstraint(NodalActor* actor,
                                   DeformableNodePositionConstraintParams const& params);
  int GetNodeIndex() const { return node_; }

 private:
  void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                  Eigen::Ref<MatrixX> jacobian) const override;

  NodalActor* actor_;
  int node_;
};

}  // namespace superdex

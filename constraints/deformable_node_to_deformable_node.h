// DeformableNodeToDeformableNode — a spring between nodes of two deformable
// actors (or two nodes of different actors: stitching, attachments).
//
//   g = T_A(X_A + u_A) − T_B(X_B + u_B)                            m = 3, n = 6
//   J = [ R_TA, −R_TB ]   (columns: node A's 3 DoFs, node B's 3 DoFs)
// Units: m, N/m, N·s/m.
#pragma once

#include <superdex/constraints/constraint.h>

namespace superdex {

class NodalActor;

struct DeformableNodeToDeformableNodeConstraintParams {
  ActorHandle actorA;       ///< a deformable actor
  ActorHandle actorB;       ///< another deformable actor
  int nodeIndexA = 0;       ///< node of A
  int nodeIndexB = 0;       ///< node of B
  real stiffness = 0;       ///< k >= 0 [N/m]
  real damping = 0;         ///< d >= 0 [N·s/m]
  real saturation = -1;     ///< ḡ [m]; <= 0 disables
};

class DeformableNodeToDeformableNodeConstraint final : public Constraint {
 public:
  DeformableNodeToDeformableNodeConstraint(NodalActor* actorA, NodalActor* actorB,
                                           DeformableNodeToDeformableNodeConstraintParams const& params);

 private:
  void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                  Eigen::Ref<MatrixX> jacobian) const override;

  NodalActor* actorA_;
  NodalActor* actorB_;
  int nodeA_, nodeB_;
};

}  // namespace superdex

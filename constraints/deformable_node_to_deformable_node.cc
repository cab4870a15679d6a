#include <superdex/constraints/deformable_node_to_deformable_node.h>

#include <superdex/actors/nodal_actor.h>

namespace superdex {

DeformableNodeToDeformableNodeConstraint::DeformableNodeToDeformableNodeConstraint(
    NodalActor* actorA, NodalActor* actorB,
    DeformableNodeToDeformableNodeConstraintParams const& params)
    : Constraint(Layout{.type = ConstraintType::DeformableNodeToDeformableNode,
                        .dimension = 3,
                        .actors = {actorA, actorB},
                        .localDofs = {actorA->GetNodePositionDofs(params.nodeIndexA),
                                      actorB->GetNodePositionDofs(params.nodeIndexB)}},
                 {params.stiffness, params.damping, params.saturation}),
      actorA_(actorA),
      actorB_(actorB),
      nodeA_(params.nodeIndexA),
      nodeB_(params.nodeIndexB) {}

void DeformableNodeToDeformableNodeConstraint::DoEvaluate(Span<real const>, Eigen::Ref<VectorX> g,
                                                          Eigen::Ref<MatrixX> jacobian) const {
  g = actorA_->GetNodePosition(nodeA_) - actorB_->GetNodePosition(nodeB_);
  jacobian.block<3, 3>(0, 0) = actorA_->GetTransformRotation().toRotationMatrix();
  jacobian.block<3, 3>(0, 3) = -actorB_->GetTransformRotation().toRotationMatrix();
}

}  // namespace superdex

#include <superdex/constraints/deformable_node_to_deformable_node.h>

#include <superdex/actors/deformable_actor.h>

namespace superdex {

DeformableNodeToDeformableNodeConstraint::DeformableNodeToDeformableNodeConstraint(
    DeformableActor* actorA, DeformableActor* actorB,
    DeformableNodeToDeformableNodeConstraintParams const& params)
    : Constraint(Layout{.type = ConstraintType::DeformableNodeToDeformableNode,
                        .dimension = 3,
                        .actors = {actorA, actorB},
                        .localDofs = {DynamicArray<int>{3 * params.nodeIndexA, 3 * params.nodeIndexA + 1,
                                                        3 * params.nodeIndexA + 2},
                                      DynamicArray<int>{3 * params.nodeIndexB, 3 * params.nodeIndexB + 1,
                                                        3 * params.nodeIndexB + 2}}},
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

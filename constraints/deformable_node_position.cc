#include <superdex/constraints/deformable_node_position.h>

#include <superdex/actors/nodal_actor.h>

namespace superdex {

DeformableNodePositionConstraint::DeformableNodePositionConstraint(
    NodalActor* actor, DeformableNodePositionConstraintParams const& params)
    : Constraint(Layout{.type = ConstraintType::DeformableNodePosition,
                        .dimension = 3,
                        .targetKind = TargetKind::Position,
                        .actors = {actor, nullptr},
                        .localDofs = {actor->GetNodePositionDofs(params.nodeIndex), DynamicArray<int>{}}},
                 {params.stiffness, params.damping, params.saturation}),
      actor_(actor),
      node_(params.nodeIndex) {
  InitializeTarget({params.position.x(), params.position.y(), params.position.z()});
}

void DeformableNodePositionConstraint::DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                                                  Eigen::Ref<MatrixX> jacobian) const {
  g = actor_->GetNodePosition(node_) - TargetPosition(target);
  jacobian = actor_->GetTransformRotation().toRotationMatrix();
}

}  // namespace superdex

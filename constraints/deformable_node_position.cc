#include <superdex/constraints/deformable_node_position.h>

#include <superdex/constraints/constraint_validation.h>

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

std::unique_ptr<Constraint> DeformableNodePositionConstraint::Create(internal::ActorLookup const& scene, DeformableNodePositionConstraintParams const& p,
                                                                    Error& error) {
  constexpr std::string_view kParams = "DeformableNodePositionConstraintParams";
  NodalActor* a = internal::GetDeformableNode(scene, p.actor, p.nodeIndex, kParams, "actor", "nodeIndex", error);
  if (!a || !internal::CheckField(p.position, kParams, "position", error) || !internal::CheckCompliance(p, kParams, error))
    return nullptr;
  return std::make_unique<DeformableNodePositionConstraint>(a, p);
}

}  // namespace superdex

#include <superdex/constraints/deformable_node_to_deformable_node.h>

#include <superdex/constraints/constraint_validation.h>

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

std::unique_ptr<Constraint> DeformableNodeToDeformableNodeConstraint::Create(internal::ActorLookup const& scene, DeformableNodeToDeformableNodeConstraintParams const& p,
                                                                            Error& error) {
  constexpr std::string_view kParams = "DeformableNodeToDeformableNodeConstraintParams";
  NodalActor* a = internal::GetDeformableNode(scene, p.actorA, p.nodeIndexA, kParams, "actorA", "nodeIndexA", error);
  if (!a) return nullptr;
  NodalActor* b = internal::GetDeformableNode(scene, p.actorB, p.nodeIndexB, kParams, "actorB", "nodeIndexB", error);
  if (!b) return nullptr;
  if (a == b) {
    error.Set(ErrorCode::InvalidArgument, std::string(kParams) +
                                              ".actorB must differ from actorA (a node-to-node spring "
                                              "couples two deformable actors), both are " +
                                              HandleText(p.actorA));
    return nullptr;
  }
  if (!internal::CheckCompliance(p, kParams, error)) return nullptr;
  return std::make_unique<DeformableNodeToDeformableNodeConstraint>(a, b, p);
}

}  // namespace superdex

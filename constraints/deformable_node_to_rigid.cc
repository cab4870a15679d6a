#include <superdex/constraints/deformable_node_to_rigid.h>

#include <superdex/constraints/constraint_validation.h>

#include <superdex/actors/nodal_actor.h>
#include <superdex/actors/rigid_actor.h>
#include <superdex/constraints/rotation_residual.h>
#include <superdex/core/so3.h>

namespace superdex {

DeformableNodeToRigidConstraint::DeformableNodeToRigidConstraint(
    NodalActor* deformable, internal::RigidBodySlot rigid, DeformableNodeToRigidConstraintParams const& params)
    : Constraint(Layout{.type = ConstraintType::DeformableNodeToRigid,
                        .dimension = 3,
                        .hasCurvature = true,
                        .actors = {deformable, rigid.actor},
                        .links = {-1, rigid.link},
                        .localDofs = {deformable->GetNodePositionDofs(params.deformableNodeIndex),
                                      DynamicArray<int>{0, 1, 2, 3, 4, 5}}},
                 {params.stiffness, params.damping, params.saturation}),
      deformable_(deformable),
      node_(params.deformableNodeIndex),
      localPos_(params.fixToDeformablePos
                    ? Real3(BodyRotation(1).conjugate() *
                            (deformable->GetNodePosition(params.deformableNodeIndex) - BodyPosition(1)))
                    : params.localPos) {}

void DeformableNodeToRigidConstraint::DoEvaluate(Span<real const>, Eigen::Ref<VectorX> g,
                                                 Eigen::Ref<MatrixX> jacobian) const {
  Real3 const arm = BodyRotation(1) * localPos_;
  g = BodyPosition(1) + arm - deformable_->GetNodePosition(node_);
  jacobian.block<3, 3>(0, 0) = -deformable_->GetTransformRotation().toRotationMatrix();
  jacobian.block<3, 3>(0, 3).setIdentity();
  jacobian.block<3, 3>(0, 6) = -Hat(arm);
}

void DeformableNodeToRigidConstraint::DoAddCurvature(Span<real const>, Eigen::Ref<VectorX const> const& weights,
                                                     Eigen::Ref<MatrixX> hessian) const {
  // the node's world position is linear in its displacement
  hessian.block<3, 3>(6, 6) +=
      internal::RotatedVectorCurvature(weights.head<3>(), BodyRotation(1) * localPos_);
}

std::unique_ptr<Constraint> DeformableNodeToRigidConstraint::Create(internal::ActorLookup const& scene, DeformableNodeToRigidConstraintParams const& p,
                                                                   Error& error) {
  constexpr std::string_view kParams = "DeformableNodeToRigidConstraintParams";
  NodalActor* d = internal::GetDeformableNode(scene, p.deformableActor, p.deformableNodeIndex, kParams,
                                         "deformableActor", "deformableNodeIndex", error);
  if (!d) return nullptr;
  internal::RigidBodySlot r;
  if (!internal::GetRigidBody(scene, p.rigidActor, p.rigidLink, kParams, "rigidActor", "rigidLink", r, error) || !internal::CheckField(p.localPos, kParams, "localPos", error) || !internal::CheckCompliance(p, kParams, error))
    return nullptr;
  return std::make_unique<DeformableNodeToRigidConstraint>(d, r, p);
}

}  // namespace superdex

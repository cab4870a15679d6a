#include <superdex/constraints/deformable_node_to_rigid.h>

#include <superdex/actors/nodal_actor.h>
#include <superdex/actors/rigid_actor.h>
#include <superdex/constraints/rotation_residual.h>
#include <superdex/core/so3.h>

namespace superdex {

DeformableNodeToRigidConstraint::DeformableNodeToRigidConstraint(
    NodalActor* deformable, RigidActor* rigid, DeformableNodeToRigidConstraintParams const& params)
    : Constraint(Layout{.type = ConstraintType::DeformableNodeToRigid,
                        .dimension = 3,
                        .hasCurvature = true,
                        .actors = {deformable, rigid},
                        .localDofs = {deformable->GetNodePositionDofs(params.deformableNodeIndex),
                                      DynamicArray<int>{0, 1, 2, 3, 4, 5}}},
                 {params.stiffness, params.damping, params.saturation}),
      deformable_(deformable),
      rigid_(rigid),
      node_(params.deformableNodeIndex),
      localPos_(params.fixToDeformablePos
                    ? Real3(rigid->GetRotation().conjugate() *
                            (deformable->GetNodePosition(params.deformableNodeIndex) - rigid->GetPosition()))
                    : params.localPos) {}

void DeformableNodeToRigidConstraint::DoEvaluate(Span<real const>, Eigen::Ref<VectorX> g,
                                                 Eigen::Ref<MatrixX> jacobian) const {
  Real3 const arm = rigid_->GetRotation() * localPos_;
  g = rigid_->GetPosition() + arm - deformable_->GetNodePosition(node_);
  jacobian.block<3, 3>(0, 0) = -deformable_->GetTransformRotation().toRotationMatrix();
  jacobian.block<3, 3>(0, 3).setIdentity();
  jacobian.block<3, 3>(0, 6) = -Hat(arm);
}

void DeformableNodeToRigidConstraint::DoAddCurvature(Span<real const>, Eigen::Ref<VectorX const> const& weights,
                                                     Eigen::Ref<MatrixX> hessian) const {
  // the node's world position is linear in its displacement
  hessian.block<3, 3>(6, 6) +=
      internal::RotatedVectorCurvature(weights.head<3>(), rigid_->GetRotation() * localPos_);
}

}  // namespace superdex

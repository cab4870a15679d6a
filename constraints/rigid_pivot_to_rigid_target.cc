#include <superdex/constraints/rigid_pivot_to_rigid_target.h>

#include <superdex/actors/rigid_actor.h>
#include <superdex/constraints/rotation_residual.h>
#include <superdex/core/so3.h>

namespace superdex {

RigidPivotToRigidTargetConstraint::RigidPivotToRigidTargetConstraint(
    RigidActor* actor, RigidPivotToRigidTargetConstraintParams const& params)
    : Constraint(Layout{.type = ConstraintType::RigidPivotToRigidTarget,
                        .dimension = 3,
                        .targetKind = TargetKind::Transform,
                        .hasCurvature = true,
                        .actors = {actor, nullptr},
                        .localDofs = {DynamicArray<int>{0, 1, 2, 3, 4, 5}, DynamicArray<int>{}}},
                 {params.stiffness, params.damping, params.saturation}),
      body_(actor),
      localPos_(params.localPos) {
  Quat const q = params.rotation.normalized();
  InitializeTarget({params.position.x(), params.position.y(), params.position.z(), q.w(), q.x(),
                    q.y(), q.z()});
}

void RigidPivotToRigidTargetConstraint::DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                                                   Eigen::Ref<MatrixX> jacobian) const {
  Real3 const arm = body_->GetRotation() * localPos_;
  Real3 const targetPoint = TargetPosition(target) + TargetRotation(target, 3) * localPos_;
  g = body_->GetPosition() + arm - targetPoint;
  jacobian.block<3, 3>(0, 0).setIdentity();
  jacobian.block<3, 3>(0, 3) = -Hat(arm);
}

void RigidPivotToRigidTargetConstraint::DoAddCurvature(Span<real const>,
                                                       Eigen::Ref<VectorX const> const& weights,
                                                       Eigen::Ref<MatrixX> hessian) const {
  // the target point is prescribed data: only the body's arm turns
  hessian.block<3, 3>(3, 3) +=
      internal::RotatedVectorCurvature(weights.head<3>(), body_->GetRotation() * localPos_);
}

}  // namespace superdex

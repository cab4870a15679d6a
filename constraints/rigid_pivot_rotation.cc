#include <superdex/constraints/rigid_pivot_rotation.h>

#include <superdex/actors/rigid_actor.h>
#include <superdex/constraints/rotation_residual.h>

namespace superdex {

RigidPivotRotationConstraint::RigidPivotRotationConstraint(
    internal::RigidBodySlot body, RigidPivotRotationConstraintParams const& params)
    : Constraint(Layout{.type = ConstraintType::RigidPivotRotation,
                        .dimension = 3,
                        .targetKind = TargetKind::Rotation,
                        .hasCurvature = true,
                        .actors = {body.actor, nullptr},
                        .links = {body.link, -1},
                        .localDofs = {DynamicArray<int>{3, 4, 5}, DynamicArray<int>{}}},
                 {params.stiffness, params.damping, params.saturation}),
      localRotation_(params.localRotation.normalized()) {
  Quat const q = params.rotation.normalized();
  InitializeTarget({q.w(), q.x(), q.y(), q.z()});
}

void RigidPivotRotationConstraint::DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                                              Eigen::Ref<MatrixX> jacobian) const {
  // g = Log(Lᵀ Q) with L = I and Q = R R_ℓ R̂ᵀ; R multiplies Q from the left
  internal::RotationResidual const r = internal::EvaluateRotationResidual(
      Quat::Identity(), BodyRotation(0) * localRotation_ * TargetRotation(target).conjugate());
  g = r.value;
  jacobian = r.derivativeQ;
}

void RigidPivotRotationConstraint::DoAddCurvature(Span<real const> target,
                                                  Eigen::Ref<VectorX const> const& weights,
                                                  Eigen::Ref<MatrixX> hessian) const {
  hessian.topLeftCorner<3, 3>() +=
      internal::RotationResidualCurvature(Quat::Identity(),
                                          BodyRotation(0) * localRotation_ * TargetRotation(target).conjugate(),
                                          weights.head<3>())
          .bottomRightCorner<3, 3>();
}

}  // namespace superdex

#include <superdex/constraints/joint_rotation_tracking.h>

#include <superdex/actors/rigid_actor.h>
#include <superdex/constraints/rotation_residual.h>

namespace superdex {

JointRotationTrackingConstraint::JointRotationTrackingConstraint(
    RigidActor* actorA, RigidActor* actorB, JointRotationTrackingConstraintParams const& params)
    : Constraint(Layout{.type = ConstraintType::JointRotationTracking,
                        .dimension = 3,
                        .targetKind = TargetKind::Rotation,
                        .hasCurvature = true,
                        .actors = {actorA, actorB},
                        .localDofs = {DynamicArray<int>{3, 4, 5}, DynamicArray<int>{3, 4, 5}}},
                 {params.stiffness, params.damping, params.saturation}),
      bodyA_(actorA),
      bodyB_(actorB),
      frameInA_((actorA->GetRotation().conjugate() * params.jointFrame).normalized()) {
  Quat const relative = (actorA->GetRotation().conjugate() * actorB->GetRotation()).normalized();
  InitializeTarget({relative.w(), relative.x(), relative.y(), relative.z()});
}

void JointRotationTrackingConstraint::DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                                                 Eigen::Ref<MatrixX> jacobian) const {
  internal::RotationResidual const r = internal::EvaluateRotationResidual(
      bodyA_->GetRotation() * TargetRotation(target) * frameInA_, bodyB_->GetRotation() * frameInA_);
  g = r.value;
  jacobian.block<3, 3>(0, 0) = -r.derivativeQ;
  jacobian.block<3, 3>(0, 3) = r.derivativeQ;
}

void JointRotationTrackingConstraint::DoAddCurvature(Span<real const> target,
                                                     Eigen::Ref<VectorX const> const& weights,
                                                     Eigen::Ref<MatrixX> hessian) const {
  // L = R_A R̂ R₀ turns with A, Q = R_B R₀ with B: the DoFs are (δL, δQ)
  hessian.topLeftCorner<6, 6>() += internal::RotationResidualCurvature(
      bodyA_->GetRotation() * TargetRotation(target) * frameInA_, bodyB_->GetRotation() * frameInA_,
      weights.head<3>());
}

}  // namespace superdex

#include <superdex/constraints/joint_rotation_tracking.h>

#include <superdex/constraints/constraint_validation.h>

#include <superdex/actors/rigid_actor.h>
#include <superdex/constraints/rotation_residual.h>

namespace superdex {

JointRotationTrackingConstraint::JointRotationTrackingConstraint(
    internal::RigidBodySlot bodyA, internal::RigidBodySlot bodyB, JointRotationTrackingConstraintParams const& params)
    : Constraint(Layout{.type = ConstraintType::JointRotationTracking,
                        .dimension = 3,
                        .targetKind = TargetKind::Rotation,
                        .hasCurvature = true,
                        .actors = {bodyA.actor, bodyB.actor},
                        .links = {bodyA.link, bodyB.link},
                        .localDofs = {DynamicArray<int>{3, 4, 5}, DynamicArray<int>{3, 4, 5}}},
                 {params.stiffness, params.damping, params.saturation}),
      frameInA_((BodyRotation(0).conjugate() * params.jointFrame).normalized()) {
  Quat const relative = (BodyRotation(0).conjugate() * BodyRotation(1)).normalized();
  InitializeTarget({relative.w(), relative.x(), relative.y(), relative.z()});
}

void JointRotationTrackingConstraint::DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                                                 Eigen::Ref<MatrixX> jacobian) const {
  internal::RotationResidual const r = internal::EvaluateRotationResidual(
      BodyRotation(0) * TargetRotation(target) * frameInA_, BodyRotation(1) * frameInA_);
  g = r.value;
  jacobian.block<3, 3>(0, 0) = -r.derivativeQ;
  jacobian.block<3, 3>(0, 3) = r.derivativeQ;
}

void JointRotationTrackingConstraint::DoAddCurvature(Span<real const> target,
                                                     Eigen::Ref<VectorX const> const& weights,
                                                     Eigen::Ref<MatrixX> hessian) const {
  // L = R_A R̂ R₀ turns with A, Q = R_B R₀ with B: the DoFs are (δL, δQ)
  hessian.topLeftCorner<6, 6>() += internal::RotationResidualCurvature(
      BodyRotation(0) * TargetRotation(target) * frameInA_, BodyRotation(1) * frameInA_,
      weights.head<3>());
}

std::unique_ptr<Constraint> JointRotationTrackingConstraint::Create(internal::ActorLookup const& scene, JointRotationTrackingConstraintParams const& p,
                                                                   Error& error) {
  constexpr std::string_view kParams = "JointRotationTrackingConstraintParams";
  internal::RigidBodySlot a, b;
  if (!internal::GetRigidPair(scene, p, kParams, a, b, error) ||
      !internal::CheckField(p.jointFrame, kParams, "jointFrame", error) || !internal::CheckCompliance(p, kParams, error))
    return nullptr;
  return std::make_unique<JointRotationTrackingConstraint>(a, b, p);
}

}  // namespace superdex

#include <superdex/constraints/joint_rotation_range.h>

#include <superdex/constraints/constraint_validation.h>

#include <superdex/actors/rigid_actor.h>
#include <superdex/constraints/rotation_residual.h>

namespace superdex {

JointRotationRangeConstraint::JointRotationRangeConstraint(
    internal::RigidBodySlot bodyA, internal::RigidBodySlot bodyB, JointRotationRangeConstraintParams const& params)
    : Constraint(Layout{.type = ConstraintType::JointRotationRange,
                        .dimension = 3,
                        .isRange = true,
                        .hasCurvature = true,
                        .actors = {bodyA.actor, bodyB.actor},
                        .links = {bodyA.link, bodyB.link},
                        .localDofs = {DynamicArray<int>{3, 4, 5}, DynamicArray<int>{3, 4, 5}}},
                 {params.stiffness, params.damping, params.saturation}),
      frameInA_((BodyRotation(0).conjugate() * params.jointFrame).normalized()),
      referenceRotation_(Quat::Identity()),
      lowerLimits_(params.lowerLimits),
      upperLimits_(params.upperLimits) {
  referenceRotation_ = params.rangeAroundRest
                           ? (frameInA_.conjugate() * BodyRotation(0).conjugate() *
                              BodyRotation(1) * frameInA_)
                                 .normalized()
                           : params.referenceRotation.normalized();
}

Real3 JointRotationRangeConstraint::GetRelativeRotation() const {
  RefreshLinkFrames();
  // r_AB = Log((R_A R₀)ᵀ (R_B R₀ R_refᵀ))
  return Log((BodyRotation(0) * frameInA_).conjugate() *
             (BodyRotation(1) * frameInA_ * referenceRotation_.conjugate()));
}

void JointRotationRangeConstraint::DoEvaluate(Span<real const>, Eigen::Ref<VectorX> g,
                                              Eigen::Ref<MatrixX> jacobian) const {
  internal::RotationResidual const r = internal::EvaluateRotationResidual(
      BodyRotation(0) * frameInA_,
      BodyRotation(1) * frameInA_ * referenceRotation_.conjugate());
  for (int j = 0; j < 3; ++j) {
    real slope;
    g[j] = internal::OneSidedViolation(r.value[j], lowerLimits_[j], upperLimits_[j], slope);
    jacobian.block<1, 3>(j, 0) = -slope * r.derivativeQ.row(j);
    jacobian.block<1, 3>(j, 3) = slope * r.derivativeQ.row(j);
  }
}

void JointRotationRangeConstraint::DoGetLimits(DynamicArray<real>& lower,
                                               DynamicArray<real>& upper) const {
  lower.assign(lowerLimits_.begin(), lowerLimits_.end());
  upper.assign(upperLimits_.begin(), upperLimits_.end());
}

void JointRotationRangeConstraint::DoAddCurvature(Span<real const>, Eigen::Ref<VectorX const> const& weights,
                                                  Eigen::Ref<MatrixX> hessian) const {
  Quat const left = BodyRotation(0) * frameInA_;
  Quat const right = BodyRotation(1) * frameInA_ * referenceRotation_.conjugate();
  Real3 const x = Log(left.conjugate() * right);
  Real3 w;
  for (int j = 0; j < 3; ++j) {
    real slope;
    internal::OneSidedViolation(x[j], lowerLimits_[j], upperLimits_[j], slope);
    w[j] = slope * weights[j];
  }
  hessian.topLeftCorner<6, 6>() += internal::RotationResidualCurvature(left, right, w);
}

std::unique_ptr<Constraint> JointRotationRangeConstraint::Create(internal::ActorLookup const& scene, JointRotationRangeConstraintParams const& p,
                                                                Error& error) {
  constexpr std::string_view kParams = "JointRotationRangeConstraintParams";
  internal::RigidBodySlot a, b;
  if (!internal::GetRigidPair(scene, p, kParams, a, b, error) ||
      !internal::CheckField(p.jointFrame, kParams, "jointFrame", error) ||
      !internal::CheckField(p.referenceRotation, kParams, "referenceRotation", error) ||
      !internal::CheckCompliance(p, kParams, error))
    return nullptr;
  for (int j = 0; j < 3; ++j)
    if (!internal::CheckLimits(p.lowerLimits[j], p.upperLimits[j],
                     std::string(kParams) + ".lowerLimits/upperLimits[" + std::to_string(j) + "]",
                     error))
      return nullptr;
  return std::make_unique<JointRotationRangeConstraint>(a, b, p);
}

}  // namespace superdex

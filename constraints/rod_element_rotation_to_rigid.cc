#include <superdex/constraints/rod_element_rotation_to_rigid.h>

#include <superdex/constraints/constraint_validation.h>

#include <superdex/actors/rigid_actor.h>
#include <superdex/actors/rod_actor.h>
#include <superdex/constraints/rotation_residual.h>

namespace superdex {

namespace {
Quat MaterialRotation(RodActor const& rod, int element) {
  return Quat(rod.GetMaterialFrame(element)).normalized();
}
}  // namespace

RodElementRotationToRigidConstraint::RodElementRotationToRigidConstraint(
    internal::RigidBodySlot rigid, RodActor* rod, RodElementRotationToRigidConstraintParams const& params)
    : Constraint(Layout{.type = ConstraintType::RodElementRotationToRigid,
                        .dimension = 3,
                        .targetKind = TargetKind::Rotation,
                        .hasCurvature = true,
                        .actors = {rigid.actor, rod},
                        .links = {rigid.link, -1},
                        .localDofs = {DynamicArray<int>{3, 4, 5},
                                      DynamicArray<int>{4 * params.elementIndex, 4 * params.elementIndex + 1,
                                                        4 * params.elementIndex + 2, 4 * params.elementIndex + 3,
                                                        4 * params.elementIndex + 4, 4 * params.elementIndex + 5,
                                                        4 * params.elementIndex + 6, 4 * params.elementIndex + 7}}},
                 {params.stiffness, params.damping, params.saturation}),
      rod_(rod),
      element_(params.elementIndex),
      frameInBody_((BodyRotation(0).conjugate() * params.jointFrame).normalized()) {
  Quat const relative = (BodyRotation(0).conjugate() * MaterialRotation(*rod, element_)).normalized();
  InitializeTarget({relative.w(), relative.x(), relative.y(), relative.z()});
}

void RodElementRotationToRigidConstraint::DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                                                     Eigen::Ref<MatrixX> jacobian) const {
  internal::RotationResidual const r = internal::EvaluateRotationResidual(
      BodyRotation(0) * TargetRotation(target) * frameInBody_,
      MaterialRotation(*rod_, element_) * frameInBody_);
  g = r.value;
  jacobian.block<3, 3>(0, 0) = -r.derivativeQ;
  jacobian.block<3, 8>(0, 3) = r.derivativeQ * rod_->GetMaterialFrameJacobian(element_);
}

void RodElementRotationToRigidConstraint::DoAddCurvature(Span<real const> target,
                                                         Eigen::Ref<VectorX const> const& weights,
                                                         Eigen::Ref<MatrixX> hessian) const {
  // wᵀ Log(Lᵀ Exp(−δL) Rₑ(e, θ) R₀), L = R_R R̂ R₀, over 7 variables: δL (0..2),
  // the element's edge vector e (3..5) and twist θ (6); e = x_{i+1} − x_i
  // then maps them to the 11 DoFs [δθ_R, x_i, θ_i, x_{i+1}, θ_{i+1}]
  using J7 = internal::Jet<7>;
  internal::JetMatrix3<4> const frame4 = rod_->GetMaterialFrameJet(element_);
  internal::JetMatrix3<7> frame;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      internal::Jet<4> const& x = frame4[r][c];
      J7& y = frame[r][c];
      y.value = x.value;
      y.gradient.tail<4>() = x.gradient;
      y.hessian.bottomRightCorner<4, 4>() = x.hessian;
    }
  Quat const left = BodyRotation(0) * TargetRotation(target) * frameInBody_;
  internal::JetMatrix3<7> const m = internal::Multiply(
      internal::Multiply(internal::TurnedLeftTransposed<7>(left, 0), frame), frameInBody_.toRotationMatrix());
  internal::JetVector3<7> const phi = internal::LogJet(m);
  J7 const contracted = weights[0] * phi[0] + weights[1] * phi[1] + weights[2] * phi[2];
  Eigen::Matrix<real, 7, 11> map = Eigen::Matrix<real, 7, 11>::Zero();
  map.block<3, 3>(0, 0).setIdentity();
  map.block<3, 3>(3, 3) = -Real33::Identity();
  map.block<3, 3>(3, 7).setIdentity();
  map(6, 6) = 1;
  hessian.topLeftCorner<11, 11>() += map.transpose() * contracted.hessian * map;
}

std::unique_ptr<Constraint> RodElementRotationToRigidConstraint::Create(internal::ActorLookup const& scene, RodElementRotationToRigidConstraintParams const& p,
                                                                       Error& error) {
  constexpr std::string_view kParams = "RodElementRotationToRigidConstraintParams";
  internal::RigidBodySlot r;
  if (!internal::GetRigidBody(scene, p.rigidActor, p.rigidLink, kParams, "rigidActor", "rigidLink", r, error)) return nullptr;
  RodActor* rod = internal::GetActorAs<RodActor>(scene, p.rodActor, std::string(kParams) + ".rodActor", error);
  if (!rod) return nullptr;
  if (p.elementIndex < 0 || p.elementIndex >= rod->GetNumElements()) {
    error.Set(ErrorCode::InvalidArgument, std::string(kParams) + ".elementIndex must be in [0, " +
                                              std::to_string(rod->GetNumElements()) + "), got " +
                                              std::to_string(p.elementIndex));
    return nullptr;
  }
  if (!internal::CheckField(p.jointFrame, kParams, "jointFrame", error) || !internal::CheckCompliance(p, kParams, error))
    return nullptr;
  return std::make_unique<RodElementRotationToRigidConstraint>(r, rod, p);
}

}  // namespace superdex

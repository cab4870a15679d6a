#include <superdex/constraints/articulated_joint_constraints.h>

#include <superdex/constraints/constraint_validation.h>

#include <superdex/actors/articulated_actor.h>
#include <superdex/constraints/rotation_residual.h>
#include <superdex/core/so3.h>

namespace superdex {

namespace {
DynamicArray<int> SingleDof(ArticulatedActor const& actor, int joint, int dof) {
  return {actor.GetJointDofOffset(joint) + dof};
}

/// The local DoFs of a spherical joint, or a free joint's rotation.
DynamicArray<int> RotationDofs(ArticulatedActor const& actor, int joint) {
  int const first = actor.GetJointDofOffset(joint) + (actor.GetJointType(joint) == JointType::Free ? 3 : 0);
  return {first, first + 1, first + 2};
}
}  // namespace

ArticulatedSingleDofConstraint::ArticulatedSingleDofConstraint(
    ArticulatedActor* actor, ArticulatedSingleDofTargetConstraintParams const& params)
    : Constraint(Layout{.type = ConstraintType::ArticulatedSingleDofTarget,
                        .dimension = 1,
                        .targetKind = TargetKind::Dof,
                        .actors = {actor, nullptr},
                        .localDofs = {SingleDof(*actor, params.jointIndex, params.dofIndex), DynamicArray<int>{}}},
                 {params.stiffness, params.damping, params.saturation}),
      actor_(actor),
      joint_(params.jointIndex),
      dof_(params.dofIndex) {
  InitializeTarget({params.target});
}

ArticulatedSingleDofConstraint::ArticulatedSingleDofConstraint(
    ArticulatedActor* actor, ArticulatedSingleDofRangeConstraintParams const& params)
    : Constraint(Layout{.type = ConstraintType::ArticulatedSingleDofRange,
                        .dimension = 1,
                        .isRange = true,
                        .actors = {actor, nullptr},
                        .localDofs = {SingleDof(*actor, params.jointIndex, params.dofIndex), DynamicArray<int>{}}},
                 {params.stiffness, params.damping, params.saturation}),
      actor_(actor),
      joint_(params.jointIndex),
      dof_(params.dofIndex),
      lower_(params.lowerLimit),
      upper_(params.upperLimit) {}

real ArticulatedSingleDofConstraint::GetCoordinate() const { return actor_->GetJointCoordinate(joint_, dof_); }

void ArticulatedSingleDofConstraint::DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                                                Eigen::Ref<MatrixX> jacobian) const {
  real const theta = GetCoordinate();
  if (IsRange()) {
    real slope;
    g[0] = internal::OneSidedViolation(theta, lower_, upper_, slope);
    jacobian(0, 0) = slope;
  } else {
    g[0] = theta - target[0];
    jacobian(0, 0) = 1;
  }
}

void ArticulatedSingleDofConstraint::DoGetLimits(DynamicArray<real>& lower, DynamicArray<real>& upper) const {
  lower.assign(1, lower_);
  upper.assign(1, upper_);
}

Articulated3dRotationConstraint::Articulated3dRotationConstraint(
    ArticulatedActor* actor, Articulated3dRotationTargetConstraintParams const& params)
    : Constraint(Layout{.type = ConstraintType::Articulated3dRotationTarget,
                        .dimension = 3,
                        .targetKind = TargetKind::Rotation,
                        .hasCurvature = true,
                        .actors = {actor, nullptr},
                        .localDofs = {RotationDofs(*actor, params.jointIndex), DynamicArray<int>{}}},
                 {params.stiffness, params.damping, params.saturation}),
      actor_(actor),
      joint_(params.jointIndex) {
  Quat const target = params.targetFromCurrent ? actor->GetJointRotation(joint_) : params.rotation.normalized();
  InitializeTarget({target.w(), target.x(), target.y(), target.z()});
}

Articulated3dRotationConstraint::Articulated3dRotationConstraint(
    ArticulatedActor* actor, Articulated3dRotationRangeConstraintParams const& params)
    : Constraint(Layout{.type = ConstraintType::Articulated3dRotationRange,
                        .dimension = 3,
                        .isRange = true,
                        .hasCurvature = true,
                        .actors = {actor, nullptr},
                        .localDofs = {RotationDofs(*actor, params.jointIndex), DynamicArray<int>{}}},
                 {params.stiffness, params.damping, params.saturation}),
      actor_(actor),
      joint_(params.jointIndex),
      lower_(params.lowerLimits),
      upper_(params.upperLimits) {}

Real3 Articulated3dRotationConstraint::GetJointRotationVector() const { return Log(actor_->GetJointRotation(joint_)); }

void Articulated3dRotationConstraint::DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                                                 Eigen::Ref<MatrixX> jacobian) const {
  Quat const rotation = actor_->GetJointRotation(joint_);
  if (IsRange()) {
    // φ = Log(R_j); R_j ← R_j Exp(δ) moves φ by J_r⁻¹(φ) δ
    Real3 const phi = Log(rotation);
    Real33 const dPhi = RightJacobianInverse(phi);
    for (int k = 0; k < 3; ++k) {
      real slope;
      g[k] = internal::OneSidedViolation(phi[k], lower_[k], upper_[k], slope);
      jacobian.row(k) = slope * dPhi.row(k);
    }
  } else {
    // g = Log(R_j R̂ᵀ); R_j Exp(δ) R̂ᵀ = Exp(R_j δ) R_j R̂ᵀ, so dg/dδ = J_l⁻¹(g) R_j
    Real3 const value = Log(rotation * TargetRotation(target).conjugate());
    g = value;
    jacobian = LeftJacobianInverse(value) * rotation.toRotationMatrix();
  }
}

void Articulated3dRotationConstraint::DoGetLimits(DynamicArray<real>& lower, DynamicArray<real>& upper) const {
  lower.assign(lower_.begin(), lower_.end());
  upper.assign(upper_.begin(), upper_.end());
}

void Articulated3dRotationConstraint::DoAddCurvature(Span<real const> target,
                                                     Eigen::Ref<VectorX const> const& weights,
                                                     Eigen::Ref<MatrixX> hessian) const {
  Quat const rotation = actor_->GetJointRotation(joint_);
  if (IsRange()) {
    // Log(R_j Exp(δ)) = Log(Lᵀ Exp(δ) Q) with L = R_jᵀ, Q = I
    Real3 const phi = Log(rotation);
    Real3 w;
    for (int k = 0; k < 3; ++k) {
      real slope;
      internal::OneSidedViolation(phi[k], lower_[k], upper_[k], slope);
      w[k] = slope * weights[k];
    }
    hessian.topLeftCorner<3, 3>() +=
        internal::RotationResidualCurvature(rotation.conjugate(), Quat::Identity(), w).bottomRightCorner<3, 3>();
  } else {
    // R_j Exp(δ) R̂ᵀ = Exp(R_j δ) R_j R̂ᵀ: the world increment is R_j δ
    Real33 const r = rotation.toRotationMatrix();
    hessian.topLeftCorner<3, 3>() +=
        r.transpose() *
        internal::RotationResidualCurvature(Quat::Identity(), rotation * TargetRotation(target).conjugate(),
                                            weights.head<3>())
            .bottomRightCorner<3, 3>() *
        r;
  }
}

std::unique_ptr<Constraint> ArticulatedSingleDofConstraint::Create(internal::ActorLookup const& scene, ArticulatedSingleDofTargetConstraintParams const& p,
                                                                  Error& error) {
  constexpr std::string_view kParams = "ArticulatedSingleDofTargetConstraintParams";
  ArticulatedActor* a = internal::GetArticulatedJoint(scene, p.actor, p.jointIndex, p.dofIndex, false, kParams, error);
  if (!a || !internal::CheckFinite(p.target, std::string(kParams) + ".target", error) ||
      !internal::CheckCompliance(p, kParams, error))
    return nullptr;
  return std::make_unique<ArticulatedSingleDofConstraint>(a, p);
}

std::unique_ptr<Constraint> ArticulatedSingleDofConstraint::Create(internal::ActorLookup const& scene, ArticulatedSingleDofRangeConstraintParams const& p,
                                                                  Error& error) {
  constexpr std::string_view kParams = "ArticulatedSingleDofRangeConstraintParams";
  ArticulatedActor* a = internal::GetArticulatedJoint(scene, p.actor, p.jointIndex, p.dofIndex, false, kParams, error);
  if (!a || !internal::CheckLimits(p.lowerLimit, p.upperLimit, std::string(kParams) + ".lowerLimit/upperLimit", error) ||
      !internal::CheckCompliance(p, kParams, error))
    return nullptr;
  return std::make_unique<ArticulatedSingleDofConstraint>(a, p);
}

std::unique_ptr<Constraint> Articulated3dRotationConstraint::Create(internal::ActorLookup const& scene, Articulated3dRotationTargetConstraintParams const& p,
                                                                   Error& error) {
  constexpr std::string_view kParams = "Articulated3dRotationTargetConstraintParams";
  ArticulatedActor* a = internal::GetArticulatedJoint(scene, p.actor, p.jointIndex, 0, true, kParams, error);
  if (!a || !internal::CheckField(p.rotation, kParams, "rotation", error) || !internal::CheckCompliance(p, kParams, error))
    return nullptr;
  return std::make_unique<Articulated3dRotationConstraint>(a, p);
}

std::unique_ptr<Constraint> Articulated3dRotationConstraint::Create(internal::ActorLookup const& scene, Articulated3dRotationRangeConstraintParams const& p,
                                                                   Error& error) {
  constexpr std::string_view kParams = "Articulated3dRotationRangeConstraintParams";
  ArticulatedActor* a = internal::GetArticulatedJoint(scene, p.actor, p.jointIndex, 0, true, kParams, error);
  if (!a) return nullptr;
  for (int j = 0; j < 3; ++j)
    if (!internal::CheckLimits(p.lowerLimits[j], p.upperLimits[j],
                     std::string(kParams) + ".lowerLimits/upperLimits[" + std::to_string(j) + "]", error))
      return nullptr;
  if (!internal::CheckCompliance(p, kParams, error)) return nullptr;
  return std::make_unique<Articulated3dRotationConstraint>(a, p);
}

}  // namespace superdex

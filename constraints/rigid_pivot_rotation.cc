#include <superdex/constraints/rigid_pivot_rotation.h>

#include <superdex/constraints/constraint_validation.h>

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

std::unique_ptr<Constraint> RigidPivotRotationConstraint::Create(internal::ActorLookup const& scene, RigidPivotRotationConstraintParams const& p,
                                                                Error& error) {
  constexpr std::string_view kParams = "RigidPivotRotationConstraintParams";
  internal::RigidBodySlot a;
  if (!internal::GetRigidBody(scene, p.actor, p.link, kParams, "actor", "link", a, error) || !internal::CheckField(p.localRotation, kParams, "localRotation", error) ||
      !internal::CheckField(p.rotation, kParams, "rotation", error) || !internal::CheckCompliance(p, kParams, error))
    return nullptr;
  return std::make_unique<RigidPivotRotationConstraint>(a, p);
}

}  // namespace superdex

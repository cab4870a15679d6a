#include <superdex/constraints/rigid_pivot_to_rigid_target.h>

#include <superdex/constraints/constraint_validation.h>

#include <superdex/actors/rigid_actor.h>
#include <superdex/constraints/rotation_residual.h>
#include <superdex/core/so3.h>

namespace superdex {

RigidPivotToRigidTargetConstraint::RigidPivotToRigidTargetConstraint(
    internal::RigidBodySlot body, RigidPivotToRigidTargetConstraintParams const& params)
    : Constraint(Layout{.type = ConstraintType::RigidPivotToRigidTarget,
                        .dimension = 3,
                        .targetKind = TargetKind::Transform,
                        .hasCurvature = true,
                        .actors = {body.actor, nullptr},
                        .links = {body.link, -1},
                        .localDofs = {DynamicArray<int>{0, 1, 2, 3, 4, 5}, DynamicArray<int>{}}},
                 {params.stiffness, params.damping, params.saturation}),
      localPos_(params.localPos) {
  Quat const q = params.rotation.normalized();
  InitializeTarget({params.position.x(), params.position.y(), params.position.z(), q.w(), q.x(),
                    q.y(), q.z()});
}

void RigidPivotToRigidTargetConstraint::DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                                                   Eigen::Ref<MatrixX> jacobian) const {
  Real3 const arm = BodyRotation(0) * localPos_;
  Real3 const targetPoint = TargetPosition(target) + TargetRotation(target, 3) * localPos_;
  g = BodyPosition(0) + arm - targetPoint;
  jacobian.block<3, 3>(0, 0).setIdentity();
  jacobian.block<3, 3>(0, 3) = -Hat(arm);
}

void RigidPivotToRigidTargetConstraint::DoAddCurvature(Span<real const>,
                                                       Eigen::Ref<VectorX const> const& weights,
                                                       Eigen::Ref<MatrixX> hessian) const {
  // the target point is prescribed data: only the body's arm turns
  hessian.block<3, 3>(3, 3) +=
      internal::RotatedVectorCurvature(weights.head<3>(), BodyRotation(0) * localPos_);
}

std::unique_ptr<Constraint> RigidPivotToRigidTargetConstraint::Create(internal::ActorLookup const& scene, RigidPivotToRigidTargetConstraintParams const& p,
                                                                     Error& error) {
  constexpr std::string_view kParams = "RigidPivotToRigidTargetConstraintParams";
  internal::RigidBodySlot a;
  if (!internal::GetRigidBody(scene, p.actor, p.link, kParams, "actor", "link", a, error) || !internal::CheckField(p.localPos, kParams, "localPos", error) ||
      !internal::CheckField(p.position, kParams, "position", error) ||
      !internal::CheckField(p.rotation, kParams, "rotation", error) || !internal::CheckCompliance(p, kParams, error))
    return nullptr;
  return std::make_unique<RigidPivotToRigidTargetConstraint>(a, p);
}

}  // namespace superdex

#include <superdex/constraints/rigid_pivot_position.h>

#include <superdex/constraints/constraint_validation.h>

#include <superdex/actors/rigid_actor.h>
#include <superdex/constraints/rotation_residual.h>
#include <superdex/core/so3.h>

namespace superdex {

RigidPivotPositionConstraint::RigidPivotPositionConstraint(
    internal::RigidBodySlot body, RigidPivotPositionConstraintParams const& params)
    : Constraint(Layout{.type = ConstraintType::RigidPivotPosition,
                        .dimension = 3,
                        .targetKind = TargetKind::Position,
                        .hasCurvature = true,
                        .actors = {body.actor, nullptr},
                        .links = {body.link, -1},
                        .localDofs = {DynamicArray<int>{0, 1, 2, 3, 4, 5}, DynamicArray<int>{}}},
                 {params.stiffness, params.damping, params.saturation}),
      localPos_(params.localPos) {
  InitializeTarget({params.position.x(), params.position.y(), params.position.z()});
}

void RigidPivotPositionConstraint::DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                                              Eigen::Ref<MatrixX> jacobian) const {
  Real3 const arm = BodyRotation(0) * localPos_;
  g = BodyPosition(0) + arm - TargetPosition(target);
  jacobian.block<3, 3>(0, 0).setIdentity();
  jacobian.block<3, 3>(0, 3) = -Hat(arm);
}

void RigidPivotPositionConstraint::DoAddCurvature(Span<real const>, Eigen::Ref<VectorX const> const& weights,
                                                  Eigen::Ref<MatrixX> hessian) const {
  hessian.block<3, 3>(3, 3) +=
      internal::RotatedVectorCurvature(weights.head<3>(), BodyRotation(0) * localPos_);
}

std::unique_ptr<Constraint> RigidPivotPositionConstraint::Create(internal::ActorLookup const& scene, RigidPivotPositionConstraintParams const& p,
                                                                Error& error) {
  constexpr std::string_view kParams = "RigidPivotPositionConstraintParams";
  internal::RigidBodySlot a;
  if (!internal::GetRigidBody(scene, p.actor, p.link, kParams, "actor", "link", a, error) || !internal::CheckField(p.localPos, kParams, "localPos", error) ||
      !internal::CheckField(p.position, kParams, "position", error) || !internal::CheckCompliance(p, kParams, error))
    return nullptr;
  return std::make_unique<RigidPivotPositionConstraint>(a, p);
}

}  // namespace superdex

#include <superdex/constraints/rod_element_rotation_to_rigid.h>

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
    RigidActor* rigid, RodActor* rod, RodElementRotationToRigidConstraintParams const& params)
    : Constraint(Layout{.type = ConstraintType::RodElementRotationToRigid,
                        .dimension = 3,
                        .targetKind = TargetKind::Rotation,
                        .actors = {rigid, rod},
                        .localDofs = {DynamicArray<int>{3, 4, 5},
                                      DynamicArray<int>{4 * params.elementIndex, 4 * params.elementIndex + 1,
                                                        4 * params.elementIndex + 2, 4 * params.elementIndex + 3,
                                                        4 * params.elementIndex + 4, 4 * params.elementIndex + 5,
                                                        4 * params.elementIndex + 6, 4 * params.elementIndex + 7}}},
                 {params.stiffness, params.damping, params.saturation}),
      rigid_(rigid),
      rod_(rod),
      element_(params.elementIndex),
      frameInBody_((rigid->GetRotation().conjugate() * params.jointFrame).normalized()) {
  Quat const relative = (rigid->GetRotation().conjugate() * MaterialRotation(*rod, element_)).normalized();
  InitializeTarget({relative.w(), relative.x(), relative.y(), relative.z()});
}

void RodElementRotationToRigidConstraint::DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                                                     Eigen::Ref<MatrixX> jacobian) const {
  internal::RotationResidual const r = internal::EvaluateRotationResidual(
      rigid_->GetRotation() * TargetRotation(target) * frameInBody_,
      MaterialRotation(*rod_, element_) * frameInBody_);
  g = r.value;
  jacobian.block<3, 3>(0, 0) = -r.derivativeQ;
  jacobian.block<3, 8>(0, 3) = r.derivativeQ * rod_->GetMaterialFrameJacobian(element_);
}

}  // namespace superdex

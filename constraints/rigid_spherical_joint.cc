#include <superdex/constraints/rigid_spherical_joint.h>

#include <superdex/constraints/constraint_validation.h>

#include <superdex/actors/rigid_actor.h>
#include <superdex/constraints/rotation_residual.h>
#include <superdex/core/so3.h>

namespace superdex {

RigidSphericalJointConstraint::RigidSphericalJointConstraint(
    internal::RigidBodySlot bodyA, internal::RigidBodySlot bodyB, RigidSphericalJointConstraintParams const& params)
    : Constraint(Layout{.type = ConstraintType::RigidSphericalJoint,
                        .dimension = 3,
                        .hasCurvature = true,
                        .actors = {bodyA.actor, bodyB.actor},
                        .links = {bodyA.link, bodyB.link},
                        .localDofs = {DynamicArray<int>{0, 1, 2, 3, 4, 5},
                                      DynamicArray<int>{0, 1, 2, 3, 4, 5}}},
                 {params.stiffness, params.damping, params.saturation}),
      localPosA_(params.localPosA),
      localPosB_(params.localPosB) {}

void RigidSphericalJointConstraint::DoEvaluate(Span<real const>, Eigen::Ref<VectorX> g,
                                               Eigen::Ref<MatrixX> jacobian) const {
  Real3 const armA = BodyRotation(0) * localPosA_;
  Real3 const armB = BodyRotation(1) * localPosB_;
  g = (BodyPosition(0) + armA) - (BodyPosition(1) + armB);
  jacobian.block<3, 3>(0, 0).setIdentity();
  jacobian.block<3, 3>(0, 3) = -Hat(armA);
  jacobian.block<3, 3>(0, 6) = -Real33::Identity();
  jacobian.block<3, 3>(0, 9) = Hat(armB);
}

void RigidSphericalJointConstraint::DoAddCurvature(Span<real const>, Eigen::Ref<VectorX const> const& weights,
                                                   Eigen::Ref<MatrixX> hessian) const {
  // g is linear in the translations; each arm turns with its body
  Real3 const w = weights.head<3>();
  hessian.block<3, 3>(3, 3) += internal::RotatedVectorCurvature(w, BodyRotation(0) * localPosA_);
  hessian.block<3, 3>(9, 9) -= internal::RotatedVectorCurvature(w, BodyRotation(1) * localPosB_);
}

std::unique_ptr<Constraint> RigidSphericalJointConstraint::Create(internal::ActorLookup const& scene, RigidSphericalJointConstraintParams const& p,
                                                                 Error& error) {
  constexpr std::string_view kParams = "RigidSphericalJointConstraintParams";
  internal::RigidBodySlot a, b;
  if (!internal::GetRigidPair(scene, p, kParams, a, b, error) ||
      !internal::CheckField(p.localPosA, kParams, "localPosA", error) ||
      !internal::CheckField(p.localPosB, kParams, "localPosB", error) || !internal::CheckCompliance(p, kParams, error))
    return nullptr;
  return std::make_unique<RigidSphericalJointConstraint>(a, b, p);
}

}  // namespace superdex

#include <superdex/constraints/rigid_prismatic_joint.h>

#include <superdex/constraints/constraint_validation.h>

#include <superdex/actors/rigid_actor.h>
#include <superdex/constraints/rotation_residual.h>
#include <superdex/core/so3.h>

namespace superdex {

RigidPrismaticJointConstraint::RigidPrismaticJointConstraint(
    internal::RigidBodySlot bodyA, internal::RigidBodySlot bodyB, RigidPrismaticJointConstraintParams const& params)
    : Constraint(Layout{.type = ConstraintType::RigidPrismaticJoint,
                        .dimension = 3,
                        .hasCurvature = true,
                        .actors = {bodyA.actor, bodyB.actor},
                        .links = {bodyA.link, bodyB.link},
                        .localDofs = {DynamicArray<int>{0, 1, 2, 3, 4, 5}, DynamicArray<int>{0, 1, 2}}},
                 {params.stiffness, params.damping, params.saturation}),
      frameInA_((BodyRotation(0).conjugate() * params.jointFrame).normalized()),
      referenceOffset_(Real3::Zero()),
      lowerLimit_(params.lowerLimit),
      upperLimit_(params.upperLimit) {
  referenceOffset_ = params.offsetAroundRest ? Offset() : params.referenceOffset;
}

Real3 RigidPrismaticJointConstraint::GetOffset() const {
  RefreshLinkFrames();
  return Offset();
}

Real3 RigidPrismaticJointConstraint::Offset() const {
  Quat const frame = BodyRotation(0) * frameInA_;
  return frame.conjugate() * (BodyPosition(1) - BodyPosition(0)) - referenceOffset_;
}

void RigidPrismaticJointConstraint::DoEvaluate(Span<real const>, Eigen::Ref<VectorX> g,
                                               Eigen::Ref<MatrixX> jacobian) const {
  Real33 const frameT = (BodyRotation(0) * frameInA_).conjugate().toRotationMatrix();
  Real3 const separation = BodyPosition(1) - BodyPosition(0);
  Real3 const s = frameT * separation - referenceOffset_;
  // ds/dt_A = −F, ds/dδθ_A = F Hat(t_B − t_A), ds/dt_B = F, with F = R₀ᵀ R_Aᵀ
  jacobian.block<3, 3>(0, 0) = -frameT;
  jacobian.block<3, 3>(0, 3) = frameT * Hat(separation);
  jacobian.block<3, 3>(0, 6) = frameT;
  g.head<2>() = s.head<2>();
  // third row: signed violation of the travel limits
  if (s.z() > upperLimit_) {
    g[2] = s.z() - upperLimit_;
  } else if (s.z() < lowerLimit_) {
    g[2] = s.z() - lowerLimit_;
  } else {
    g[2] = 0;
    jacobian.row(2).setZero();
  }
}

void RigidPrismaticJointConstraint::DoAddCurvature(Span<real const>, Eigen::Ref<VectorX const> const& weights,
                                                   Eigen::Ref<MatrixX> hessian) const {
  // wᵀs = Wᵀ Exp(−δθ_A) (t_B − t_A) + const with W = R_A R₀ w (the travel
  // row's weight only where a limit is violated): second order ½ δ×(δ×d) in
  // δθ_A, and −Wᵀ(δθ_A × d) couples δθ_A with d = t_B − t_A through Hat(W)
  real const travel = Offset().z();
  Real3 w = weights.head<3>();
  if (!(travel > upperLimit_ || travel < lowerLimit_)) w.z() = 0;
  Real3 const worldWeights = (BodyRotation(0) * frameInA_) * w;
  Real3 const separation = BodyPosition(1) - BodyPosition(0);
  Real33 const coupling = Hat(worldWeights);
  hessian.block<3, 3>(3, 3) += internal::RotatedVectorCurvature(worldWeights, separation);
  hessian.block<3, 3>(3, 6) += coupling;
  hessian.block<3, 3>(6, 3) -= coupling;
  hessian.block<3, 3>(3, 0) -= coupling;
  hessian.block<3, 3>(0, 3) += coupling;
}

std::unique_ptr<Constraint> RigidPrismaticJointConstraint::Create(internal::ActorLookup const& scene, RigidPrismaticJointConstraintParams const& p,
                                                                 Error& error) {
  constexpr std::string_view kParams = "RigidPrismaticJointConstraintParams";
  internal::RigidBodySlot a, b;
  if (!internal::GetRigidPair(scene, p, kParams, a, b, error) ||
      !internal::CheckField(p.jointFrame, kParams, "jointFrame", error) ||
      !internal::CheckField(p.referenceOffset, kParams, "referenceOffset", error) ||
      !internal::CheckLimits(p.lowerLimit, p.upperLimit, std::string(kParams) + ".lowerLimit/upperLimit", error) ||
      !internal::CheckCompliance(p, kParams, error))
    return nullptr;
  return std::make_unique<RigidPrismaticJointConstraint>(a, b, p);
}

}  // namespace superdex

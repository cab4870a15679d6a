#include <superdex/actors/rigid_actor.h>

#include <cmath>

#include <superdex/assembly/hessian_assembler.h>
#include <superdex/core/so3.h>
#include <superdex/core/validate.h>
#include <superdex/stage/integrator.h>

namespace superdex {

std::unique_ptr<RigidActor> RigidActor::Create(RigidActorParams const& params, Error& error) {
  using namespace internal;
  if (!CheckPositive(params.mass, "RigidActorParams.mass", error) ||
      !CheckPositive(params.inertia, "RigidActorParams.inertia", error) ||
      !CheckFinite(params.position, "RigidActorParams.position", error) ||
      !CheckUnitQuat(params.rotation, "RigidActorParams.rotation", error) ||
      !CheckFinite(params.linearVelocity, "RigidActorParams.linearVelocity", error) ||
      !CheckFinite(params.angularVelocity, "RigidActorParams.angularVelocity", error))
    return nullptr;
  std::unique_ptr<RigidActor> actor(new RigidActor());
  actor->mass_ = params.mass;
  actor->inertia_ = params.inertia;
  actor->state_.position = params.position;
  actor->state_.rotation = params.rotation.normalized();
  actor->state_.linearVelocity = params.linearVelocity;
  actor->state_.angularVelocity = params.angularVelocity;
  return actor;
}

bool RigidActor::SetPose(Real3 const& position, Quat const& rotation, Error& error) {
  if (!internal::CheckFinite(position, "position", error) ||
      !internal::CheckUnitQuat(rotation, "rotation", error))
    return false;
  state_.position = position;
  state_.rotation = rotation.normalized();
  state_.hasHistory = false;
  return true;
}

bool RigidActor::SetVelocity(Real3 const& linearVelocity, Real3 const& angularVelocity,
                             Error& error) {
  if (!internal::CheckFinite(linearVelocity, "linearVelocity", error) ||
      !internal::CheckFinite(angularVelocity, "angularVelocity", error))
    return false;
  state_.linearVelocity = linearVelocity;
  state_.angularVelocity = angularVelocity;
  state_.hasHistory = false;
  return true;
}

Real3 RigidActor::TransformPoint(Real3 const& localPoint) const {
  return state_.position + state_.rotation * localPoint;
}

Real3 RigidActor::GetAngularMomentum() const {
  Quat const& q = state_.rotation;
  return q * (inertia_.asDiagonal() * (q.conjugate() * state_.angularVelocity));
}

real RigidActor::GetKineticEnergy() const {
  Real3 const bodyOmega = state_.rotation.conjugate() * state_.angularVelocity;
  return 0.5 * mass_ * state_.linearVelocity.squaredNorm() +
         0.5 * bodyOmega.dot(inertia_.asDiagonal() * bodyOmega);
}

void RigidActor::AppendDofBlockSizes(DynamicArray<int>& sizes) const { sizes.push_back(kNumDofs); }

void RigidActor::WriteRigidBodyModes(Eigen::Ref<MatrixX> modes) const {
  // translation DoFs move with v = t + ω × x; the rotation DoFs are world-frame
  // increments, so they take ω itself
  auto block = modes.middleRows(dofOffset_, kNumDofs);
  block.setZero();
  block.topLeftCorner<3, 3>().setIdentity();
  block.topRightCorner<3, 3>() = -Hat(GetPosition());
  block.bottomRightCorner<3, 3>().setIdentity();
}

void RigidActor::WriteDofLengthScales(Span<real> scales) const {
  // rms distance of the mass from the centre: tr I_b = 2 ∫ r² dm
  real const radius = std::sqrt(inertia_.sum() / (2 * mass_));
  for (int i = 0; i < 3; ++i) {
    scales[dofOffset_ + i] = 1;
    scales[dofOffset_ + 3 + i] = radius;
  }
}

void RigidActor::WriteDofInverseMasses(Span<real> inverseMasses) const {
  // M = diag(m, m, m, R I_b Rᵀ) in (t, δθ): the world-frame inertia's diagonal
  // (R I_b Rᵀ)_jj = Σₖ R_jk² I_k
  Real33 const r = state_.rotation.toRotationMatrix();
  Real3 const worldDiagonal = r.cwiseAbs2() * inertia_;
  for (int i = 0; i < 3; ++i) {
    inverseMasses[dofOffset_ + i] = 1 / mass_;
    inverseMasses[dofOffset_ + 3 + i] = 1 / worldDiagonal[i];
  }
}

void RigidActor::AppendContributorDofs(DynamicArray<DynamicArray<int>>& dofLists) const {
  DynamicArray<int> dofs(kNumDofs);
  for (int i = 0; i < kNumDofs; ++i) dofs[i] = dofOffset_ + i;
  dofLists.push_back(std::move(dofs));
}


void RigidActor::BeginStage(internal::StageContext const& context) {
  internal::StageCoefficients const& requested = context.coefficients;
  Real3 const& gravity = context.gravity;
  stage_ = requested.ForBody(state_.hasHistory);
  gravity_ = gravity;
  inertiaStage_.Begin(stage_, mass_, inertia_, state_);
}

real RigidActor::Energy(internal::OwnedContributors owned) const {
  if (!owned(0)) return 0;  // its one contributor
  return inertiaStage_.Energy(state_.position, state_.rotation) - mass_ * gravity_.dot(state_.position);
}

void RigidActor::AddGradientAndHessian(internal::HessianAssembler& assembler, int firstContributor,
                                         internal::AssemblyOptions const& options) const {
  bool const projectHessian = options.projectHessian;
  if (!assembler.Evaluates(firstContributor)) return;
  // the exact rotational inertia Hessian adds the curvature of φ(δθ) against
  // w I_b (φ − φ̂), indefinite far from φ̂; projected, the block is the
  // Gauss–Newton one (PSD)
  Real3 force, torque;
  Real33 rotationHessian;
  inertiaStage_.Derivatives(state_.position, state_.rotation, force, torque, &rotationHessian, projectHessian);
  force -= mass_ * gravity_;
  Eigen::Matrix<real, 6, 1> gradient;
  gradient << force, torque;
  assembler.AddGradient(firstContributor, gradient);
  Eigen::Matrix<real, 6, 6> hessian = Eigen::Matrix<real, 6, 6>::Zero();
  hessian.topLeftCorner<3, 3>().diagonal().setConstant(inertiaStage_.TranslationStiffness());
  hessian.bottomRightCorner<3, 3>() = rotationHessian;
  assembler.AddBlock(firstContributor, hessian);
}

void RigidActor::SaveIterate() {
  savedPosition_ = state_.position;
  savedRotation_ = state_.rotation;
}

void RigidActor::RestoreIterate() {
  state_.position = savedPosition_;
  state_.rotation = savedRotation_;
}

void RigidActor::ApplyIncrementFromSaved(Span<real const> delta, real alpha) {
  Real3 const dt(delta[dofOffset_], delta[dofOffset_ + 1], delta[dofOffset_ + 2]);
  Real3 const dr(delta[dofOffset_ + 3], delta[dofOffset_ + 4], delta[dofOffset_ + 5]);
  state_.position = savedPosition_ + alpha * dt;
  state_.rotation = (Exp(alpha * dr) * savedRotation_).normalized();
}

bool RigidActor::IsStateFinite() const {
  return state_.position.allFinite() && state_.rotation.coeffs().allFinite();
}

void RigidActor::EndStage() { inertiaStage_.End(state_.position, state_.rotation, state_); }

void RigidActor::SaveSnapshot(std::unique_ptr<internal::ActorSnapshot>& snapshot) const {
  internal::SaveStateSnapshot(state_, snapshot);
}

void RigidActor::RestoreSnapshot(internal::ActorSnapshot const& snapshot) {
  internal::RestoreStateSnapshot(snapshot, state_);
}

}  // namespace superdex

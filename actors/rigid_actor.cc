#include <superdex/actors/rigid_actor.h>

#include <superdex/assembly/hessian_assembler.h>
#include <superdex/core/so3.h>
#include <superdex/core/validate.h>
#include <superdex/scene/integrator.h>

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

void RigidActor::AppendContributorDofs(DynamicArray<DynamicArray<int>>& dofLists) const {
  DynamicArray<int> dofs(kNumDofs);
  for (int i = 0; i < kNumDofs; ++i) dofs[i] = dofOffset_ + i;
  dofLists.push_back(std::move(dofs));
}

namespace internal {
Real3 SolveMomentumConservingRotation(Real3 const& inertia, Real3 const& omega, real h) {
  // f(x) = Exp(h x) I x − I Ω; J_f = Exp(h x)(I − h Hat(I x) J_r(h x))
  Real3 const momentum = inertia.asDiagonal() * omega;
  real const scale = momentum.norm();
  if (scale == 0) return Real3::Zero();
  Real3 x = omega;
  auto residual = [&](Real3 const& y) -> Real3 {
    return ExpMatrix(h * y) * (inertia.asDiagonal() * y) - momentum;
  };
  Real3 f = residual(x);
  for (int iteration = 0; iteration < 30 && f.norm() > 1e-15 * scale; ++iteration) {
    Real33 const rotation = ExpMatrix(h * x);
    Real33 const jacobian =
        rotation * (Real33(inertia.asDiagonal()) - h * Hat(inertia.asDiagonal() * x) * RightJacobian(h * x));
    Real3 const step = jacobian.partialPivLu().solve(-f);
    // damped: halve the step until the residual decreases
    real alpha = 1;
    Real3 trial = x + step;
    Real3 fTrial = residual(trial);
    while (fTrial.norm() >= f.norm() && alpha > 1e-6) {
      alpha *= 0.5;
      trial = x + alpha * step;
      fTrial = residual(trial);
    }
    if (fTrial.norm() >= f.norm()) break;
    x = trial;
    f = fTrial;
  }
  return x;
}
}  // namespace internal

void RigidActor::BeginStage(internal::StageCoefficients const& requested, Real3 const& gravity) {
  stage_ = (requested.usesHistory && !state_.hasHistory)
               ? internal::MakeStage(IntegratorType::BackwardEuler, requested.duration, false)
               : requested;
  internal::StageCoefficients const& stage = stage_;
  real const h = stage.duration;
  real const betaH = stage.beta * h;
  Quat const& rotation = state_.rotation;
  Quat const rotationT = rotation.conjugate();
  stageStartPosition_ = state_.position;
  stageStartRotation_ = rotation;
  gravity_ = gravity;
  weight_ = stage.InertiaWeight();

  // translation target Δ̂ = c Δₚ + β h (a vⁿ + b vⁿ⁻¹)
  Real3 velocity = stage.aVelocity * state_.linearVelocity;
  previousStageOffset_.setZero();
  if (stage.usesHistory) {
    velocity += stage.bVelocity * state_.previousLinearVelocity;
    previousStageOffset_ = state_.previousPosition - state_.position;
  }
  targetTranslation_ = stage.cPrevious * previousStageOffset_ + betaH * velocity;

  // rotation target in the body frame at stage start
  Real3 const bodyOmega = rotationT * state_.angularVelocity;
  previousRotationOffset_.setZero();
  if (stage.usesHistory) {
    Real3 const bodyOmegaPrevious = rotationT * state_.previousAngularVelocity;
    previousRotationOffset_ = Log(rotationT * state_.previousRotation);
    Real3 const omegaMix = stage.aVelocity * bodyOmega + stage.bVelocity * bodyOmegaPrevious;
    Real3 const omegaExtrapolated = 2 * bodyOmega - bodyOmegaPrevious;
    Real3 const gyroscopic = omegaExtrapolated.cross(inertia_.asDiagonal() * omegaExtrapolated);
    targetRotation_ = stage.cPrevious * previousRotationOffset_ + betaH * omegaMix -
                      betaH * betaH * inertia_.cwiseInverse().asDiagonal() * gyroscopic;
  } else {
    targetRotation_ = betaH * internal::SolveMomentumConservingRotation(inertia_, bodyOmega, betaH);
  }
}

Real3 RigidActor::StageRotation() const {
  return Log(stageStartRotation_.conjugate() * state_.rotation);
}

real RigidActor::Energy() const {
  Real3 const dt = state_.position - stageStartPosition_ - targetTranslation_;
  Real3 const dr = StageRotation() - targetRotation_;
  return 0.5 * weight_ * (mass_ * dt.squaredNorm() + dr.dot(inertia_.asDiagonal() * dr)) -
         mass_ * gravity_.dot(state_.position);
}

void RigidActor::AddGradientAndHessian(Span<real> gradient, internal::HessianAssembler& assembler,
                                       int firstContributor, bool /*projectHessian*/) const {
  // the rigid inertia block is PSD by construction: nothing to project
  Real3 const phi = StageRotation();
  // dφ/dδθ = J_l⁻¹(φ) Rⁿᵀ
  Real33 const dPhi = LeftJacobianInverse(phi) * stageStartRotation_.conjugate().toRotationMatrix();
  Real3 const gradTranslation =
      weight_ * mass_ * (state_.position - stageStartPosition_ - targetTranslation_) - mass_ * gravity_;
  Real3 const gradRotation = dPhi.transpose() * (weight_ * (inertia_.asDiagonal() * (phi - targetRotation_)));
  for (int i = 0; i < 3; ++i) {
    gradient[dofOffset_ + i] += gradTranslation[i];
    gradient[dofOffset_ + 3 + i] += gradRotation[i];
  }
  Eigen::Matrix<real, 6, 6> hessian = Eigen::Matrix<real, 6, 6>::Zero();
  hessian.topLeftCorner<3, 3>().diagonal().setConstant(weight_ * mass_);
  hessian.bottomRightCorner<3, 3>() = weight_ * dPhi.transpose() * inertia_.asDiagonal() * dPhi;
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

void RigidActor::EndStage() {
  internal::StageCoefficients const& stage = stage_;
  real const betaH = stage.beta * stage.duration;
  Real3 const velocity =
      (state_.position - stageStartPosition_ - stage.cPrevious * previousStageOffset_) / betaH;
  Real3 const bodyOmega = (StageRotation() - stage.cPrevious * previousRotationOffset_) / betaH;
  state_.previousPosition = stageStartPosition_;
  state_.previousRotation = stageStartRotation_;
  state_.previousLinearVelocity = state_.linearVelocity;
  state_.previousAngularVelocity = state_.angularVelocity;
  state_.hasHistory = true;
  state_.linearVelocity = velocity;
  state_.angularVelocity = stageStartRotation_ * bodyOmega;
}

void RigidActor::SaveSnapshot(std::unique_ptr<internal::ActorSnapshot>& snapshot) const {
  auto* own = dynamic_cast<Snapshot*>(snapshot.get());
  if (!own) {
    snapshot = std::make_unique<Snapshot>();
    own = static_cast<Snapshot*>(snapshot.get());
  }
  own->state = state_;
}

void RigidActor::RestoreSnapshot(internal::ActorSnapshot const& snapshot) {
  state_ = static_cast<Snapshot const&>(snapshot).state;
}

}  // namespace superdex

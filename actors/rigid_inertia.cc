#include <superdex/actors/rigid_inertia.h>

#include <array>
#include <cmath>

namespace superdex::internal {

void RigidInertiaStage::Begin(StageCoefficients const& stage, real mass, Real3 const& inertia,
                              RigidBodyMotion const& motion) {
  stage_ = stage;
  mass_ = mass;
  inertia_ = inertia;
  real const betaH = stage.beta * stage.duration;
  Quat const rotationT = motion.rotation.conjugate();
  startPosition_ = motion.position;
  startRotation_ = motion.rotation;
  weight_ = stage.InertiaWeight();

  // translation target Δ̂ = c Δₚ + β h (a vⁿ + b vⁿ⁻¹)
  Real3 velocity = stage.aVelocity * motion.linearVelocity;
  previousOffset_.setZero();
  if (stage.usesHistory) {
    velocity += stage.bVelocity * motion.previousLinearVelocity;
    previousOffset_ = motion.previousPosition - motion.position;
  }
  targetTranslation_ = stage.cPrevious * previousOffset_ + betaH * velocity;

  // rotation target in the body frame at the stage start
  Real3 const bodyOmega = rotationT * motion.angularVelocity;
  previousRotationOffset_.setZero();
  if (stage.usesHistory) {
    // BDF2 in the chart R = Rⁿ Exp(x) around the stage start, where a curve's
    // rate is ẋ = J_r⁻¹(x) Ω = J_l⁻¹(x) Rⁿᵀ ω (Ω body, ω world) and its
    // acceleration ẍ = J_r⁻¹(x) Ω̇ + O(h²). The J factors are O(h) rotations
    // that a second-order method must keep: the previous pose's rate, and
    // the gyroscopic acceleration −I⁻¹(Ω̃ × I Ω̃) at the predicted x̃, with
    // Ω̃ = 2Ωⁿ − Ωⁿ⁻¹ extrapolated in body components.
    previousRotationOffset_ = Log(rotationT * motion.previousRotation);
    Real3 const previousRate =
        LeftJacobianInverse(previousRotationOffset_) * (rotationT * motion.previousAngularVelocity);
    Real3 const bodyOmegaPrevious = motion.previousRotation.conjugate() * motion.previousAngularVelocity;
    Real3 const omegaMix = stage.aVelocity * bodyOmega + stage.bVelocity * previousRate;
    Real3 const predicted = stage.cPrevious * previousRotationOffset_ + betaH * omegaMix;
    Real3 const omegaExtrapolated = 2 * bodyOmega - bodyOmegaPrevious;
    Real3 const gyroscopic = omegaExtrapolated.cross(inertia.asDiagonal() * omegaExtrapolated);
    targetRotation_ =
        predicted - betaH * betaH * (RightJacobianInverse(predicted) * (inertia.cwiseInverse().asDiagonal() * gyroscopic));
  } else {
    targetRotation_ = betaH * SolveMomentumConservingRotation(inertia, bodyOmega, betaH);
  }
}

real RigidInertiaStage::Energy(Real3 const& position, Quat const& rotation, real* roundOffScale) const {
  Real3 const dt = position - startPosition_ - targetTranslation_;
  Real3 const dr = StageRotation(rotation) - targetRotation_;
  Real3 const moment = inertia_.cwiseProduct(dr);
  if (roundOffScale != nullptr)
    *roundOffScale = weight_ * (mass_ * dt.norm() *
                                    (position.norm() + startPosition_.norm() + targetTranslation_.norm()) +
                                moment.norm());
  return 0.5 * weight_ * (mass_ * dt.squaredNorm() + dr.dot(moment));
}

void RigidInertiaStage::Derivatives(Real3 const& position, Quat const& rotation, Real3& force, Real3& torque,
                                    Real33* rotationHessian, bool gaussNewton) const {
  // dφ/dδθ = J_l⁻¹(φ) Rⁿᵀ; one Log and one J_l⁻¹ serve the gradient and the
  // Hessian (an articulated chain's assembly evaluated each twice per link)
  Real3 const phi = StageRotation(rotation);
  Real33 const inverse = LeftJacobianInverse(phi);
  Real33 const rn = startRotation_.toRotationMatrix();
  Real3 const lambda = weight_ * inertia_.cwiseProduct(phi - targetRotation_);  // w I (φ − φ̂)
  force = weight_ * mass_ * (position - startPosition_ - targetTranslation_);
  torque = rn * (inverse.transpose() * lambda);
  if (rotationHessian == nullptr) return;
  Real33 hessian = weight_ * inverse.transpose() * inertia_.asDiagonal() * inverse;
  if (!gaussNewton) {
    // E(u) = ½ w eᵀ I e, e = φ(u) − φ̂, φ(u) = Log(Exp(u) M₀), M₀ = Rⁿᵀ R,
    // u = Rⁿᵀ δθ. Along u = t a, φ̇ = J_l⁻¹(φ) a and φ̈ = D(J_l⁻¹)(φ)[b] a with
    // b = J_l⁻¹(φ) a, so aᵀ H a = w φ̇ᵀ I φ̇ + λᵀ φ̈ with λ = w I e. With
    // J_l⁻¹(φ) = 1 − ½Φ + γ(θ) Φ² (Φ = [φ]×, θ = |φ|),
    //   λᵀ D(J_l⁻¹)(φ)[b] a = bᵀ M a,
    //   M = ½[λ]× + (γ′/θ) φ (Φ² λ)ᵀ − γ ([λ]× Φ + [λ × φ]×),
    // and H = J_l⁻ᵀ w I J_l⁻¹ + sym(J_l⁻ᵀ M). (A closed form of what
    // second-order jets of Log ∘ Exp gave: 38 % of an articulated chain's
    // step went to those; rigid_inertia_test compares the two to 1e-12.)
    real const gamma = LeftJacobianInverseCoefficient(phi.norm());
    real const gammaRate = LeftJacobianInverseCoefficientRate(phi.norm());
    Real33 const hatPhi = Hat(phi);
    Real33 const hatLambda = Hat(lambda);
    Real33 const m = 0.5 * hatLambda + gammaRate * phi * (hatPhi * hatPhi * lambda).transpose() -
                     gamma * (hatLambda * hatPhi + Hat(lambda.cross(phi)));
    Real33 const curvature = inverse.transpose() * m;
    hessian += 0.5 * (curvature + curvature.transpose());
  }
  *rotationHessian = rn * hessian * rn.transpose();
}

void RigidInertiaStage::Gradient(Real3 const& position, Quat const& rotation, Real3& force, Real3& torque) const {
  Derivatives(position, rotation, force, torque);
}

Real33 RigidInertiaStage::RotationHessianGaussNewton(Quat const& rotation) const {
  Real3 force, torque;
  Real33 hessian;
  Derivatives(startPosition_, rotation, force, torque, &hessian, true);
  return hessian;
}

Real33 RigidInertiaStage::RotationHessian(Quat const& rotation) const {
  Real3 force, torque;
  Real33 hessian;
  Derivatives(startPosition_, rotation, force, torque, &hessian);
  return hessian;
}

void RigidInertiaStage::End(Real3 const& position, Quat const& rotation, RigidBodyMotion& motion) const {
  real const betaH = stage_.beta * stage_.duration;
  Real3 const velocity = (position - startPosition_ - stage_.cPrevious * previousOffset_) / betaH;
  // the chart rate ẋ = (x − c Δₚ)/(β h) at x = φ, and ω = Rⁿ J_l(φ) ẋ in the
  // world (exact for backward Euler's torque-free step, where ẋ ∥ φ)
  Real3 const phi = StageRotation(rotation);
  Real3 const bodyOmega = LeftJacobian(phi) * ((phi - stage_.cPrevious * previousRotationOffset_) / betaH);
  motion.previousPosition = startPosition_;
  motion.previousRotation = startRotation_;
  motion.previousLinearVelocity = motion.linearVelocity;
  motion.previousAngularVelocity = motion.angularVelocity;
  motion.hasHistory = true;
  motion.position = position;
  motion.rotation = rotation;
  motion.linearVelocity = velocity;
  motion.angularVelocity = startRotation_ * bodyOmega;
}

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

}  // namespace superdex::internal

// The stage inertia term of one rigid body, shared by RigidActor and the
// links of an ArticulatedActor (the formula is in actors/rigid_actor.h):
//
//   E(t, R) = ½ w m ‖Δₜ − Δ̂ₜ‖² + ½ w (φ − φ̂)ᵀ I_b (φ − φ̂),
//   Δₜ = t − tⁿ, φ = Log(Rⁿᵀ R),
//
// t the centre of mass, R the body rotation, Δ̂ₜ and φ̂ the integrator's
// predictions from the body's velocities (with the gyroscopic treatment of
// rigid_actor.h). Derivatives are w.r.t. a translation of t and a world-frame
// rotation increment R ← Exp(δθ) R. Gravity is not part of it.
#pragma once

#include <superdex/core/so3.h>
#include <superdex/core/types.h>
#include <superdex/stage/integrator.h>

namespace superdex::internal {

/// The committed motion of one rigid body and its integrator history.
struct RigidBodyMotion {
  Real3 position = Real3::Zero();         ///< centre of mass, world
  Quat rotation = Quat::Identity();       ///< body → world
  Real3 linearVelocity = Real3::Zero();   ///< world
  Real3 angularVelocity = Real3::Zero();  ///< world
  bool hasHistory = false;
  Real3 previousPosition = Real3::Zero(), previousLinearVelocity = Real3::Zero(),
        previousAngularVelocity = Real3::Zero();
  Quat previousRotation = Quat::Identity();
};

class RigidInertiaStage {
 public:
  /// Prepares the stage from the committed `motion`; `stage` must already be
  /// the effective coefficients (backward Euler for a body without history).
  void Begin(StageCoefficients const& stage, real mass, Real3 const& inertia, RigidBodyMotion const& motion);

  /// With `roundOffScale`: also the magnitude its round-off scales with, in
  /// energy units (eps times it bounds the error of E from the rounding of
  /// the pose, ~ w m |Δx − Δx̂| (|x| + |xⁿ| + |Δx̂|) + w |I (φ − φ̂)|): E is a
  /// difference of poses, so near the stage minimum it is resolved far more
  /// coarsely than its own size says.
  real Energy(Real3 const& position, Quat const& rotation, real* roundOffScale = nullptr) const;
  /// ∂E/∂t (`force`), ∂E/∂δθ (`torque`), world frame, and where
  /// `rotationHessian` is given ∂²E/∂δθ² (exact, or with `gaussNewton` its
  /// PSD Gauss–Newton part: see RotationHessian*), from one Log and one J_l⁻¹.
  void Derivatives(Real3 const& position, Quat const& rotation, Real3& force, Real3& torque,
                   Real33* rotationHessian = nullptr, bool gaussNewton = false) const;
  /// ∂E/∂t (`force`) and ∂E/∂δθ (`torque`), world frame.
  void Gradient(Real3 const& position, Quat const& rotation, Real3& force, Real3& torque) const;
  /// ∂²E/∂t² = w m I.
  real TranslationStiffness() const { return weight_ * mass_; }
  /// ∂²E/∂δθ², Gauss–Newton part Rⁿ J_l⁻ᵀ(φ) w I_b J_l⁻¹(φ) Rⁿᵀ (PSD).
  Real33 RotationHessianGaussNewton(Quat const& rotation) const;
  /// ∂²E/∂δθ², exact (adds the curvature of φ(δθ) against w I_b (φ − φ̂);
  /// second-order forward differentiation of Log).
  Real33 RotationHessian(Quat const& rotation) const;
  /// Commits the converged pose into `motion`: velocities from the stage's
  /// displacement, history for BDF2.
  void End(Real3 const& position, Quat const& rotation, RigidBodyMotion& motion) const;

  Real3 const& StartPosition() const { return startPosition_; }
  Quat const& StartRotation() const { return startRotation_; }
  real Weight() const { return weight_; }

 private:
  Real3 StageRotation(Quat const& rotation) const { return Log(startRotation_.conjugate() * rotation); }

  StageCoefficients stage_;
  real mass_ = 1, weight_ = 0;
  Real3 inertia_ = Real3::Ones();
  Real3 startPosition_ = Real3::Zero();
  Quat startRotation_ = Quat::Identity();
  Real3 targetTranslation_ = Real3::Zero();  ///< Δ̂ₜ
  Real3 targetRotation_ = Real3::Zero();     ///< φ̂, body frame at the stage start
  Real3 previousOffset_ = Real3::Zero();     ///< Δₚ, translation
  Real3 previousRotationOffset_ = Real3::Zero();  ///< Δₚ, rotation (body frame)
};

/// Ω̂ with Exp(h Ω̂) I_b Ω̂ = I_b Ω (torque-free rotation that keeps the
/// angular momentum vector). Newton from Ω; returns Ω̂.
Real3 SolveMomentumConservingRotation(Real3 const& inertia, Real3 const& bodyAngularVelocity, real h);

}  // namespace superdex::internal

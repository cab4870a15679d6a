// A rigid body: 6 DoFs, translation t (3) then a world-frame rotation
// increment δθ (3), R ← Exp(δθ) R (docs/design.md §3).
//
// Stage inertia term (scene/integrator.h for the coefficients). With
// Δₜ = t − tⁿ, the body-frame rotation φ = Log(Rⁿᵀ R) and the principal
// inertia I_b:
//
//   E = ½ w m ‖Δₜ − Δ̂ₜ‖² + ½ w (φ − φ̂)ᵀ I_b (φ − φ̂) − m g·t
//
// Gradient w.r.t. δθ: Rⁿ J_l⁻ᵀ(φ) w I_b (φ − φ̂)  (dφ/dδθ = J_l⁻¹(φ) Rⁿᵀ);
// Hessian: its Gauss–Newton part, PSD. The gyroscopic effect enters through
// φ̂: for backward Euler, φ̂ = h Ω̂ with Ω̂ solving Exp(h Ω̂) I_b Ω̂ = I_b Ωⁿ,
// so a torque-free body keeps its angular momentum vector exactly (to the
// Newton tolerance); for BDF2 the gyroscopic torque −Ω̃ × I_b Ω̃ is taken at
// the extrapolated Ω̃ = 2Ωⁿ − Ωⁿ⁻¹ (second order, no exact conservation).
#pragma once

#include <superdex/actors/actor.h>
#include <superdex/actors/rigid_inertia.h>
#include <superdex/core/error.h>
#include <superdex/stage/integrator.h>

namespace superdex {

struct RigidActorParams {
  real mass = 1;                     ///< [kg], > 0
  Real3 inertia = Real3::Ones();     ///< principal moments in the body frame [kg·m²], > 0
  Real3 position = Real3::Zero();    ///< centre of mass, world [m]
  Quat rotation = Quat::Identity();  ///< body → world, unit quaternion
  Real3 linearVelocity = Real3::Zero();   ///< [m/s]
  Real3 angularVelocity = Real3::Zero();  ///< world frame [rad/s]
};

class RigidActor final : public Actor {
 public:
  static constexpr int kNumDofs = 6;

  /// Validates `params` (mass and inertia finite and > 0, unit quaternion,
  /// finite vectors); nullptr and `error` on bad input.
  static std::unique_ptr<RigidActor> Create(RigidActorParams const& params, Error& error);

  real GetMass() const { return mass_; }
  Real3 const& GetInertia() const { return inertia_; }
  Real3 const& GetPosition() const { return state_.position; }
  Quat const& GetRotation() const { return state_.rotation; }
  Real3 const& GetLinearVelocity() const { return state_.linearVelocity; }
  /// World-frame angular velocity.
  Real3 const& GetAngularVelocity() const { return state_.angularVelocity; }
  /// Teleports the body (finite position, unit quaternion). Clears the
  /// integrator history: the next step starts like a first step.
  bool SetPose(Real3 const& position, Quat const& rotation, Error& error);
  /// Sets the velocities (finite; angular in the world frame). Clears the
  /// integrator history.
  bool SetVelocity(Real3 const& linearVelocity, Real3 const& angularVelocity, Error& error);
  /// World point of a body-frame point: T(r) = t + R r.
  Real3 TransformPoint(Real3 const& localPoint) const;
  /// Angular momentum about the centre of mass, world frame: R I_b Rᵀ ω.
  Real3 GetAngularMomentum() const;
  /// Kinetic energy ½ m v² + ½ ωᵀ R I_b Rᵀ ω.
  real GetKineticEnergy() const;

 private:
  RigidActor() : Actor(ActorType::Rigid, kNumDofs) {}

  using State = internal::RigidBodyMotion;

  void AppendDofBlockSizes(DynamicArray<int>& sizes) const override;
  void WriteRigidBodyModes(Eigen::Ref<MatrixX> modes) const override;
  void WriteDofLengthScales(Span<real> scales) const override;
  void WriteDofInverseMasses(Span<real> inverseMasses) const override;
  void AppendContributorDofs(DynamicArray<DynamicArray<int>>& dofLists) const override;
  void BeginStage(internal::StageContext const& context) override;
  real Energy(internal::OwnedContributors owned) const override;
  void AddGradientAndHessian(internal::HessianAssembler& assembler, int firstContributor,
                             internal::AssemblyOptions const& options) const override;
  void SaveIterate() override;
  void RestoreIterate() override;
  void ApplyIncrementFromSaved(Span<real const> delta, real alpha) override;
  bool IsStateFinite() const override;
  void EndStage() override;
  void SaveSnapshot(std::unique_ptr<internal::ActorSnapshot>& snapshot) const override;
  void RestoreSnapshot(internal::ActorSnapshot const& snapshot) override;

  real mass_ = 1;
  Real3 inertia_ = Real3::Ones();
  State state_;

  // stage data (scratch, rebuilt by BeginStage)
  internal::StageCoefficients stage_;  ///< effective coefficients of this stage
  internal::RigidInertiaStage inertiaStage_;
  Real3 gravity_ = Real3::Zero();
  // line-search iterate
  Real3 savedPosition_;
  Quat savedRotation_;
};


}  // namespace superdex

// Constraint: the uniform runtime interface of constraints.md, over every
// type — identity and introspection, the compliant parameters (stiffness,
// damping, saturation), kinematic targets, diagnostics, queries and limits.
//
// It is made of three parts, each in its own file:
//   ConstraintKernel  (constraint_kernel.h)  the type's kinematics: its layout,
//                     g, J and curvature; a concrete type (one file each)
//                     supplies only this
//   Constraint        (here)                 the runtime: what the API shows
//                     and sets, held in a ConstraintState
//   ConstraintStage   (constraint_stage.h)   the state of a stage, owned by the
//                     ConstraintSet the solver drives: g⁰, the linearization,
//                     the force estimate, and the compliant potential on them
//
// Methods that do not apply to a type (a target setter on a type without that
// target, limits on a non-range type) return false / empty and set an Error
// with code NotSupported naming the method and the type.
#pragma once

#include <string_view>

#include <array>

#include <superdex/constraints/compliant_potential.h>
#include <superdex/constraints/constraint_params.h>
#include <superdex/constraints/constraint_kernel.h>
#include <superdex/core/error.h>
#include <superdex/core/handle.h>
#include <superdex/core/types.h>
#include <superdex/stage/constraint_hessian.h>

namespace superdex {

enum class QueryType {
  ConstraintForce,  ///< the generalized constraint force −rᶜ at the end of the last step
};

std::string_view ToString(QueryType type);

namespace internal {
/// What a constraint holds beyond its kernel: the runtime state its API
/// reads and sets, which the scene saves and restores around a step and the
/// stage updates (effective parameters, forces, the old target).
struct ConstraintState {
  ConstraintHandle handle;
  CompliantParams params;          ///< k, d, ḡ as set
  CompliantParams stageParams;     ///< as the last stage used them (the near-rigid cap)
  bool nearRigidCapped = false;    ///< the cap lowered them in the last stage
  ConstraintHessian hessian = ConstraintHessian::SceneDefault;
  ConstraintKernel::Target target{};
  ConstraintKernel::Target oldTarget{};  ///< p̂ᵢ⁰, the target at the stage start
  bool forceQueryRegistered = false;
  bool forceValid = false;
  DynamicArray<real> force;  ///< −Jᵀf at the end of the last step (n entries)
};

/// The target a fraction s ∈ [0, 1] of the way from `from` to `to` (positions
/// and DoF values linearly, rotations by slerp); exactly `to` at s = 1 or when
/// the two are equal (sub-stepping: docs/architecture.md).
ConstraintKernel::Target InterpolateTarget(ConstraintKernel::TargetKind kind, ConstraintKernel::Target const& from,
                                           ConstraintKernel::Target const& to, real s);
}  // namespace internal

class Constraint : public internal::ConstraintKernel {
 public:
  ~Constraint() override = default;

  // ---- identity and introspection (GetType, GetNumActors, GetActor,
  // GetDofIndicesForActor, GetDimension, GetNumDofs, IsRange, HasCurvature:
  // ConstraintKernel) ----
  ConstraintHandle GetHandle() const { return state_.handle; }

  // ---- parameters (any time) ----
  real GetStiffness() const { return state_.params.stiffness; }
  real GetDamping() const { return state_.params.damping; }
  real GetSaturation() const { return state_.params.saturation; }
  /// k [N/m or N·m/rad]: finite and >= 0.
  bool SetStiffness(real stiffness, Error& error);
  /// d [N·s/m or N·m·s/rad]: finite and >= 0.
  bool SetDamping(real damping, Error& error);
  /// ḡ: finite; <= 0 (e.g. −1) disables saturation. Force cap = k ḡ.
  bool SetSaturation(real saturation, Error& error);
  /// The stiffness k and damping d the last stage used: k and d themselves,
  /// or, where the near-rigid cap (NewtonParams::nearRigidBeta) applied,
  /// both scaled so that k + d/Δtᵢ = 4π²/(β² Δtᵢ² w) (compliant_potential.h;
  /// docs/constraints.md "Near-rigid constraints"). Set to k and d by the
  /// setters, until the next stage.
  real GetEffectiveStiffness() const { return state_.stageParams.stiffness; }
  real GetEffectiveDamping() const { return state_.stageParams.damping; }
  /// True when the near-rigid cap lowered k and d in the last stage.
  bool IsNearRigidCapped() const { return state_.nearRigidCapped; }
  /// This constraint's Hessian block (SceneDefault: the scene's choice).
  ConstraintHessian GetHessianApproximation() const { return state_.hessian; }
  /// Any ConstraintHessian value; another value is an InvalidArgument Error.
  bool SetHessianApproximation(ConstraintHessian hessian, Error& error);

  // ---- kinematic targets ----
  /// Target position p̂ (RigidPivotPosition, DeformableNodePosition).
  bool SetTargetPosition(Real3 const& position, Error& error);
  /// Target rotation R̂, unit quaternion (rotation-target types).
  bool SetTargetRotation(Quat const& rotation, Error& error);
  /// Target rigid transform T̂ (RigidPivotToRigidTarget).
  bool SetTargetTransform(Real3 const& position, Quat const& rotation, Error& error);
  /// Target DoF value θ̂ (ArticulatedSingleDofTarget).
  bool SetTargetDof(real value, Error& error);
  /// Resets the stage-start target p̂ᵢ⁰ to the current target, so that a
  /// teleported target produces no damping transient in the next step.
  bool UpdateOldTarget(Error& error);

  // ---- diagnostics ----
  /// The current value g (m entries). Needs no setup.
  DynamicArray<real> GetDeviation() const;
  bool IsQuerySupported(QueryType type) const;
  /// Registers a query; ConstraintForce must be registered before a step for
  /// GetForce to report it after the step.
  bool RegisterQuery(QueryType type, Error& error);
  /// −rᶜ = −Jᵀ(κ g + d/Δtᵢ Δg) at the end of the last step, in DoF-list order
  /// (n entries). Error (InvalidState) when the ConstraintForce query was not
  /// registered before the last step, or no step ran since.
  Span<real const> GetForce(Error& error) const;

  // ---- limits (range types) ----
  /// Lower bounds of the range types (m entries; −∞ where unbounded).
  DynamicArray<real> GetLimitMinValues(Error& error) const;
  /// Upper bounds of the range types (m entries; +∞ where unbounded).
  DynamicArray<real> GetLimitMaxValues(Error& error) const;

  /// Internal: the runtime state, as the scene (handles, transactional
  /// steps, sub-steps) and the stage (constraint_stage.h) read and set it.
  /// Not part of the API.
  internal::ConstraintState& GetState() { return state_; }
  internal::ConstraintState const& GetState() const { return state_; }

 protected:
  Constraint(Layout layout, internal::CompliantParams const& params);

  Target const& GetTarget() const { return state_.target; }
  /// Sets both the target and the old target (for use at creation).
  void InitializeTarget(Target const& target);

 private:
  /// Sets a NotSupported error: "<method> does not apply to a <type> constraint<why>".
  void ReportNotSupported(std::string_view method, std::string_view why, Error& error) const;
  bool RequireTarget(TargetKind kind, std::string_view method, Error& error) const;
  DynamicArray<real> LimitsFor(bool upper, std::string_view method, Error& error) const;

  internal::ConstraintState state_;
};

}  // namespace superdex

// Constraint: the uniform runtime interface of constraints.md, over every
// type. A concrete type supplies only its kinematics — m, the DoFs it
// touches on each actor, and one DoEvaluate writing g and the dense local J
// (columns in DoF-list order) — while stiffness, damping, saturation,
// targets, the stage-start value, queries and limits live here once.
//
// Methods that do not apply to a type (a target setter on a type without that
// target, limits on a non-range type) return false / empty and set an Error
// with code NotSupported naming the method and the type.
#pragma once

#include <array>
#include <string_view>

#include <superdex/constraints/compliant_potential.h>
#include <superdex/core/error.h>
#include <superdex/core/handle.h>
#include <superdex/core/types.h>

namespace superdex {

class Actor;
class Scene;

enum class ConstraintType {
  RigidSphericalJoint,
  RigidPrismaticJoint,
  JointRotationRange,
  JointRotationTracking,
  RigidPivotPosition,
  RigidPivotToRigidTarget,
  RigidPivotRotation,
  DeformableNodePosition,
  DeformableNodeToDeformableNode,
  DeformableNodeToRigid,
  ArticulatedSingleDofTarget,
  ArticulatedSingleDofRange,
  Articulated3dRotationTarget,
  Articulated3dRotationRange,
  RodElementRotationToRigid,
};

std::string_view ToString(ConstraintType type);

enum class QueryType {
  ConstraintForce,  ///< the generalized constraint force −rᶜ at the end of the last step
};

std::string_view ToString(QueryType type);

namespace internal {
class StageSolver;
class HessianAssembler;
struct ConstraintTestAccess;  // defined by white-box tests only

/// Scratch for evaluating constraints, owned by the stage solver and sized
/// once per pattern build to the largest m and n.
struct ConstraintWorkspace {
  VectorX g, f, r;
  MatrixX jacobian, hessian;
  void Reserve(int maxDimension, int maxDofs);
};
}  // namespace internal

class Constraint {
 public:
  virtual ~Constraint() = default;
  Constraint(Constraint const&) = delete;
  Constraint& operator=(Constraint const&) = delete;

  // ---- identity and introspection ----
  ConstraintHandle GetHandle() const { return handle_; }
  ConstraintType GetType() const { return type_; }
  int GetNumActors() const { return numActors_; }
  /// The i-th actor, or nullptr when i is not in [0, GetNumActors()).
  Actor* GetActor(int i) const;
  /// Global DoF indices this constraint touches on actor i (empty span when
  /// i is out of range). Valid until the scene's topology changes.
  Span<int const> GetDofIndicesForActor(int i) const;
  /// m, the dimension of g.
  int GetDimension() const { return dimension_; }
  /// n, the number of DoFs coupled.
  int GetNumDofs() const { return static_cast<int>(dofs_.size()); }
  /// True for range (unilateral) types.
  bool IsRange() const { return isRange_; }

  // ---- parameters (any time) ----
  real GetStiffness() const { return params_.stiffness; }
  real GetDamping() const { return params_.damping; }
  real GetSaturation() const { return params_.saturation; }
  /// k [N/m or N·m/rad]: finite and >= 0.
  bool SetStiffness(real stiffness, Error& error);
  /// d [N·s/m or N·m·s/rad]: finite and >= 0.
  bool SetDamping(real damping, Error& error);
  /// ḡ: finite; <= 0 (e.g. −1) disables saturation. Force cap = k ḡ.
  bool SetSaturation(real saturation, Error& error);

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

 protected:
  enum class TargetKind { None, Position, Rotation, Transform, Dof };

  /// A type declares m, its kind of target, whether it is a range type, and
  /// for each actor the local DoFs it touches (e.g. {3,4,5}: rotation only).
  struct Layout {
    ConstraintType type;
    int dimension;
    TargetKind targetKind = TargetKind::None;
    bool isRange = false;
    std::array<Actor*, 2> actors{};
    std::array<DynamicArray<int>, 2> localDofs;
  };
  Constraint(Layout layout, internal::CompliantParams const& params);

  /// g and J (m×n, columns in DoF-list order, w.r.t. the DoF increments of
  /// design.md §3) at the actors' current configuration for `target`.
  virtual void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                          Eigen::Ref<MatrixX> jacobian) const = 0;
  /// Range types override: bounds of each component of g's measure.
  virtual void DoGetLimits(DynamicArray<real>& lower, DynamicArray<real>& upper) const;

  /// Target storage of a type: position (3), rotation quaternion (w,x,y,z),
  /// transform (position then quaternion), or one DoF value.
  static constexpr int kMaxTargetSize = 7;
  using Target = std::array<real, kMaxTargetSize>;
  Target const& GetTarget() const { return target_; }
  /// Sets both the target and the old target (for use at creation).
  void InitializeTarget(Target const& target);
  static Real3 TargetPosition(Span<real const> target);
  static Quat TargetRotation(Span<real const> target, int offset = 0);

 private:
  friend class Scene;
  friend class internal::StageSolver;
  friend struct internal::ConstraintTestAccess;

  /// Sets a NotSupported error: "<method> does not apply to a <type> constraint<why>".
  void ReportNotSupported(std::string_view method, std::string_view why, Error& error) const;
  bool RequireTarget(TargetKind kind, std::string_view method, Error& error) const;
  DynamicArray<real> GetLimits(bool upper, std::string_view method, Error& error) const;
  /// Recomputes global DoF indices from the actors' offsets.
  void RefreshDofs();
  void Evaluate(Span<real const> target, internal::ConstraintWorkspace& ws) const;

  // stage interface
  void BeginStage(internal::ConstraintWorkspace& ws);
  real Energy(real h, internal::ConstraintWorkspace& ws) const;
  void AddGradientAndHessian(real h, Span<real> gradient, internal::HessianAssembler& assembler,
                             int contributor, internal::ConstraintWorkspace& ws) const;
  void EndStage(real h, internal::ConstraintWorkspace& ws);

  ConstraintHandle handle_;
  ConstraintType type_;
  int dimension_;
  int numActors_;
  TargetKind targetKind_;
  bool isRange_;
  std::array<Actor*, 2> actors_{};
  std::array<DynamicArray<int>, 2> localDofs_;
  DynamicArray<int> dofs_;  ///< global DoF list (actor 0's, then actor 1's)
  internal::CompliantParams params_;

  Target target_{};
  Target oldTarget_{};  ///< p̂ᵢ⁰, the target at the stage start
  VectorX stageStartValue_;  ///< g(qᵢ⁰, p̂ᵢ⁰)

  bool forceQueryRegistered_ = false;
  bool forceValid_ = false;
  DynamicArray<real> force_;
};

}  // namespace superdex

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

#include <Eigen/Eigenvalues>

#include <superdex/constraints/compliant_potential.h>
#include <superdex/core/error.h>
#include <superdex/core/handle.h>
#include <superdex/core/types.h>
#include <superdex/stage/constraint_hessian.h>
#include <superdex/stage/link_path.h>
#include <superdex/stage/own_block_solve.h>
#include <superdex/stage/term_workspace.h>

namespace superdex {

class Actor;
class ArticulatedActor;
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
class ConstraintSet;
class HessianAssembler;
struct ConstraintTestAccess;  // defined by white-box tests only
using ConstraintWorkspace = TermWorkspace;

/// A rigid body a constraint acts on: a RigidActor (link −1) or link `link`
/// of an ArticulatedActor.
struct RigidBodySlot {
  Actor* actor = nullptr;
  int link = -1;
};
}  // namespace internal

class Constraint : private internal::LinkTerm {
 public:
  ~Constraint() override = default;
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
  /// True when g is nonlinear in the DoF increments (its curvature G can be
  /// non-zero); false for the deformable couplings and single-DoF types.
  bool HasCurvature() const { return hasCurvature_; }

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
  /// The stiffness k and damping d the last stage used: k and d themselves,
  /// or, where the near-rigid cap (NewtonParams::nearRigidBeta) applied,
  /// both scaled so that k + d/Δtᵢ = 4π²/(β² Δtᵢ² w) (compliant_potential.h;
  /// docs/constraints.md "Near-rigid constraints"). Set to k and d by the
  /// setters, until the next stage.
  real GetEffectiveStiffness() const { return stageParams_.stiffness; }
  real GetEffectiveDamping() const { return stageParams_.damping; }
  /// True when the near-rigid cap lowered k and d in the last stage.
  bool IsNearRigidCapped() const { return nearRigidCapped_; }
  /// This constraint's Hessian block (SceneDefault: the scene's choice).
  ConstraintHessian GetHessianApproximation() const { return hessian_; }
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

 protected:
  enum class TargetKind { None, Position, Rotation, Transform, Dof };

  /// A type declares m, its kind of target, whether it is a range type, and
  /// for each actor the local DoFs it touches (e.g. {3,4,5}: rotation only).
  /// Where actor i is an articulated link (links[i] >= 0), the type still
  /// writes J and G over the rigid-body DoFs it lists (a subset of 0..5 of
  /// the link frame's increments) and reads the frame through BodyPosition /
  /// BodyRotation; the constraint's DoFs on that actor are the joint DoFs
  /// from the root to the link, and J and G are mapped onto them through the
  /// link's kinematic Jacobian (internal::LinkPath; docs/articulated.md,
  /// "Links in constraints").
  struct Layout {
    ConstraintType type;
    int dimension;
    TargetKind targetKind = TargetKind::None;
    bool isRange = false;
    bool hasCurvature = false;  ///< g nonlinear: the type overrides DoAddCurvature
    std::array<Actor*, 2> actors{};
    std::array<int, 2> links{-1, -1};
    std::array<DynamicArray<int>, 2> localDofs;
  };
  Constraint(Layout layout, internal::CompliantParams const& params);

  /// g and J (m×n, columns in DoF-list order, w.r.t. the DoF increments of
  /// docs/design.md §3) at the actors' current configuration for `target`.
  virtual void DoEvaluate(Span<real const> target, Eigen::Ref<VectorX> g,
                          Eigen::Ref<MatrixX> jacobian) const = 0;
  /// Adds the curvature of g contracted with `weights` (m entries),
  /// Σᵢ wᵢ ∂²gᵢ/∂q² (n×n, DoF-list order, second derivatives w.r.t. the DoF
  /// increments of docs/design.md §3 at zero increment), to `hessian`, at the
  /// actors' current configuration for `target`. Types with hasCurvature
  /// override; range types include their one-sided slopes (∂²gᵢ = ±∂²xᵢ where
  /// a bound is violated, 0 inside).
  virtual void DoAddCurvature(Span<real const> target, Eigen::Ref<VectorX const> const& weights,
                              Eigen::Ref<MatrixX> hessian) const;
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
  /// The frame of the rigid body that is actor `i`: a RigidActor's pose, or
  /// an articulated link's frame at the current iterate (refreshed before
  /// every DoEvaluate and DoAddCurvature).
  Real3 BodyPosition(int i) const;
  Quat BodyRotation(int i) const;
  /// Recomputes the articulated links' frames and Jacobians at the current
  /// iterate (a type's public queries of the pose call it first).
  void RefreshLinkFrames() const;

 private:
  friend class Scene;
  friend class internal::ConstraintSet;
  friend struct internal::ConstraintTestAccess;

  /// Sets a NotSupported error: "<method> does not apply to a <type> constraint<why>".
  void ReportNotSupported(std::string_view method, std::string_view why, Error& error) const;
  bool RequireTarget(TargetKind kind, std::string_view method, Error& error) const;
  DynamicArray<real> GetLimits(bool upper, std::string_view method, Error& error) const;
  /// target_ ← the target a fraction s ∈ [0, 1] of the way from `from` to
  /// `to` (positions and DoF values linearly, rotations by slerp); exactly
  /// `to` at s = 1 or when the two are equal (sub-stepping, scene.cc).
  void SetTargetBetween(Target const& from, Target const& to, real s);
  /// Recomputes global DoF indices from the actors' offsets.
  void RefreshDofs();
  void Evaluate(Span<real const> target, internal::ConstraintWorkspace& ws) const;
  /// Adds Σᵢ wᵢ ∂²gᵢ/∂q² over the constraint's n DoFs to `hessian`, after an
  /// Evaluate at `target` with the same `ws` (links: Bᵀ G B plus the link
  /// frames' own curvature against the type's wrench Jᵀw).
  void AddCurvature(Span<real const> target, Eigen::Ref<VectorX const> const& weights,
                    internal::ConstraintWorkspace& ws, Eigen::Ref<MatrixX> hessian) const;
  bool HasLinks() const { return links_[0] >= 0 || links_[1] >= 0; }
  /// The actor slot of the articulated link the actor's tree recursion can
  /// take this constraint into (AddFoldedTerms), or −1: a single-body
  /// constraint on a link, or a two-body one between a link and a body that
  /// is not a link (a rigid body, a deformable node, a rod element; the
  /// actor then couples its tree with those DoFs by a Schur complement).
  int FoldableLinkSlot() const;
  /// This constraint as a term an own-block solve can take in (a
  /// FoldableLinkSlot constraint), or nullptr.
  internal::LinkTerm* GetLinkTerm() { return FoldableLinkSlot() >= 0 ? this : nullptr; }
  // internal::LinkTerm, on the link of FoldableLinkSlot (AddLinkTerms:
  // AddFoldedTerms with this stage's Δtᵢ and the scene's constraint Hessian)
  internal::StageDofs const* GetLinkOwner() const override;
  internal::LinkPath const& GetLinkPath() const override { return paths_[FoldableLinkSlot()]; }
  Span<int const> GetPathDofs() const override { return slotDofs_[FoldableLinkSlot()]; }
  Span<int const> GetPathColumns() const override { return slotColumns_[FoldableLinkSlot()]; }
  Span<int const> GetOtherDofs() const override;
  Span<int const> GetOtherColumns() const override;
  bool AddLinkTerms(bool projectHessian, internal::TermWorkspace& ws, internal::TermWorkspace::FoldedBlock& hessian,
                    Eigen::Matrix<real, 6, 1>& curvatureWrench, bool& exactCurvature) const override;
  /// Newton's linearization at the current iterate, recorded for the force
  /// predictions: ws.g, ws.jacobian (Evaluate), ws.f = f(g) and ws.r = Jᵀ f;
  /// returns the Gauss–Newton scale κ + d/h, or −1 for an inactive range
  /// constraint (nothing recorded, nothing to add).
  real Linearize(real h, internal::ConstraintWorkspace& ws) const;
  /// The weights of the curvature G: the force estimate f̂ once this stage
  /// has one, else f(g) (ws.f, after Linearize).
  Eigen::Ref<VectorX const> CurvatureWeights(internal::ConstraintWorkspace const& ws) const;
  /// This constraint's Hessian (SceneDefault: `sceneHessian`), GaussNewton
  /// for a type without curvature.
  ConstraintHessian HessianMode(ConstraintHessian sceneHessian) const;
  /// hessian += G, or with `diagonal` the diagonal of G's column norms (PSD).
  static void AddCurvatureTerm(Eigen::Ref<MatrixX const> const& curvature, bool diagonal,
                               Eigen::Ref<MatrixX> hessian);
  /// A constraint folded into its articulated actor's tree (FoldableLinkSlot
  /// `linkSlot`; the actor calls this in its assembly instead of the scene's
  /// constraint loop): the gradient Jᵀ f over the constraint's DoFs in ws.r
  /// (slot order), and the Hessian H = (κ + d/h) J_typeᵀ J_type + G_type (G's
  /// diagonal column norms when projecting or with GeometricStiffnessDiagonal;
  /// none for GaussNewton) in `hessian`, (6 + n_o)², over the link frame's
  /// increments (δt; δθ) first and then the other body's n_o DoFs in their
  /// list order (n_o = 0 for a single-body constraint); the wrench
  /// (F; M) = J_typeᵀ w on the link that weighs the link frame's own
  /// curvature in `curvatureWrench` (zero for GaussNewton), with
  /// `exactCurvature` false where that curvature is to be taken by its
  /// column norms (as G's). Returns false when it adds nothing (an inactive
  /// range constraint).
  bool AddFoldedTerms(real h, ConstraintHessian sceneHessian, bool projectHessian, int linkSlot,
                      internal::ConstraintWorkspace& ws, internal::TermWorkspace::FoldedBlock& hessian,
                      Eigen::Matrix<real, 6, 1>& curvatureWrench, bool& exactCurvature) const;

  // stage interface
  /// Records g(qᵢ⁰, p̂ᵢ⁰) and this stage's compliant parameters: with
  /// `nearRigidBeta` > 0, k and d capped by the near-rigid rule with w the
  /// largest diagonal entry of J diag(`inverseMasses`) Jᵀ at the stage start
  /// (`inverseMasses`: the scene's per-DoF estimate, Actor::
  /// WriteDofInverseMasses; unread when the cap is off). Returns whether the
  /// cap applied.
  bool BeginStage(real h, real nearRigidBeta, Span<real const> inverseMasses,
                  internal::ConstraintWorkspace& ws);
  /// w = maxᵢ Σⱼ J_ij² inverseMasses[dofⱼ] from the Jacobian in `ws`.
  real InverseEffectiveMass(Span<real const> inverseMasses, internal::ConstraintWorkspace const& ws) const;
  real Energy(real h, internal::ConstraintWorkspace& ws) const;
  /// `sceneHessian` is the scene's choice, used where this constraint's own
  /// is SceneDefault; with `projectHessian` the block is PSD.
  /// Also records Newton's linearization (g and J here) for the two calls
  /// below. The geometric stiffness is weighted with the force estimate f̂
  /// (PredictForce) once one exists in this stage, else with f(g).
  /// Safe to run concurrently for different constraints, each with its own
  /// workspace (it writes only this constraint's linearization).
  void AddGradientAndHessian(real h, internal::HessianAssembler& assembler,
                             int contributor, ConstraintHessian sceneHessian, bool projectHessian,
                             internal::ConstraintWorkspace& ws) const;
  /// After the line search accepted α δ (`delta` in global DoF order): the
  /// force estimate f̂ ← f(g + α J δ), the force of the linearized constraint
  /// at the new iterate (the multiplier update of a primal–dual Newton step).
  /// With `corrected`, the step was δ + δc of a second-order correction and
  /// `delta` is δc: f̂ ← f(g(q + δ) + J δc), the correction's own multiplier.
  void PredictForce(real h, Span<real const> delta, real alpha, bool corrected = false);
  /// g += α J δ with J of the last linearization (`delta` in global DoF order).
  void AddLinearizedChange(Span<real const> delta, real alpha, Eigen::Ref<VectorX> g) const;
  /// At a trial configuration q + δ: adds Jᵀ (f(g(q + δ)) − f(g + J δ)) to
  /// `gradient`, the force of g's second-order error along δ, with J from the
  /// last linearization (the right-hand side of a second-order correction),
  /// and records g(q + δ).
  void AddCorrectionForce(real h, Span<real const> delta, Span<real> gradient,
                          internal::ConstraintWorkspace& ws);
  void EndStage(real h, internal::ConstraintWorkspace& ws);

  ConstraintHandle handle_;
  ConstraintType type_;
  int dimension_;
  int numActors_;
  TargetKind targetKind_;
  bool isRange_;
  bool hasCurvature_;
  ConstraintHessian hessian_ = ConstraintHessian::SceneDefault;
  std::array<Actor*, 2> actors_{};
  std::array<DynamicArray<int>, 2> localDofs_;
  /// global DoF list: actor 0's, then actor 1's not listed yet (two links of
  /// one articulated actor, a kinematic loop, share their common path DoFs)
  DynamicArray<int> dofs_;
  /// per actor: its DoFs (global; GetDofIndicesForActor) and their columns in dofs_
  std::array<DynamicArray<int>, 2> slotDofs_, slotColumns_;
  /// per actor: the link it is (−1: the actor itself), the type's rigid DoFs
  /// on it where it is a link, and the link's path and frame
  std::array<int, 2> links_{-1, -1};
  std::array<DynamicArray<int>, 2> typeDofs_;
  mutable std::array<internal::LinkPath, 2> paths_;
  int typeNumDofs_ = 0;
  internal::CompliantParams params_;
  /// this stage's Δtᵢ and the scene's constraint Hessian (BeginStage)
  real stageDuration_ = 1;
  ConstraintHessian sceneHessian_ = ConstraintHessian::GeometricStiffness;
  internal::CompliantParams stageParams_;  ///< params_, or its near-rigid cap, for this stage
  bool nearRigidCapped_ = false;

  Target target_{};
  Target oldTarget_{};  ///< p̂ᵢ⁰, the target at the stage start
  VectorX stageStartValue_;  ///< g(qᵢ⁰, p̂ᵢ⁰)
  // Newton's last linearization (sized at BeginStage; a cache the const
  // assembly writes): g, J, whether the constraint takes part, and the force
  // estimate f̂ for the curvature
  mutable VectorX linearValue_;
  VectorX trialValue_;  ///< g(q + δ) at the last second-order correction
  mutable MatrixX linearJacobian_;
  mutable bool linearActive_ = false;
  VectorX forceEstimate_;
  bool forceEstimateValid_ = false;

  bool forceQueryRegistered_ = false;
  bool forceValid_ = false;
  DynamicArray<real> force_;
};

}  // namespace superdex

// The stage contract: what every contributor to a stage implements, and what
// every owner of configuration DoFs implements (docs/architecture.md, "The
// stage contract").
//
// A stage minimizes its incremental potential
//
//   Eᵢ(q) = Σ_terms Eₜ(q)
//
// over the configuration q, the concatenation of the DoF owners' blocks
// (StageDofs). Each term (StageTerm) gives its energy, its gradient and
// Hessian blocks through the assembler, and its stencil: the DoF lists of its
// assembler contributors (one dense block each). Actors are both: their
// inertia, gravity and elastic energy is a term over their own DoFs.
// Constraints (and, later, contacts) are terms over the DoFs of the bodies
// they join. The Newton solver (solver/) sees nothing else: it walks the
// terms and the DoF owners in a fixed order, and knows no kind of body or
// constraint.
#pragma once

#include <string>

#include <superdex/assembly/hessian_assembler.h>
#include <superdex/core/types.h>
#include <superdex/stage/constraint_hessian.h>
#include <superdex/stage/integrator.h>

namespace superdex::internal {

class OwnBlockSolve;
class LinkTerm;

/// What every term knows of the stage it is part of.
struct StageContext {
  StageCoefficients coefficients;  ///< the integrator's; Δtᵢ = coefficients.duration
  Real3 gravity = Real3::Zero();
  /// The scene's constraint Hessian (never SceneDefault), for terms whose
  /// own choice is SceneDefault.
  ConstraintHessian constraintHessian = ConstraintHessian::GeometricStiffness;
  /// The near-rigid cap β (0: off) and, when on, the per-DoF inverse-mass
  /// estimate 1/M_jj at the committed configuration (StageDofs::
  /// WriteDofInverseMasses), indexed by global DoF.
  real nearRigidBeta = 0;
  Span<real const> inverseMasses;
  /// The threads a term may run its own loops on during the stage (its
  /// safe step, its candidate search; results must not depend on their
  /// number); nullptr: serially. Outlives the stage.
  ParallelExecutor const* executor = nullptr;
};

/// Eᵢ and the magnitude of its round-off, summed term by term in a fixed
/// order (bit-identical for any thread or rank count).
struct EnergySum {
  real energy = 0;
  /// Σ (|term| + its round-off scale): the scale of Eᵢ's resolution.
  real scale = 0;
  /// Adds one term; `roundOffScale` is the magnitude its round-off scales
  /// with beyond |term| (0 when |term| is the scale: see StageTerm::AddEnergy).
  void Add(real term, real roundOffScale = 0) {
    energy += term;
    scale += std::abs(term) + roundOffScale;
  }
};

/// How one assembly forms its blocks.
struct AssemblyOptions {
  /// Every block positive semi-definite (element Hessians projected, the
  /// constraints' curvature by its column norms, inertia Gauss–Newton).
  bool projectHessian = false;
  /// The assembler's index of this term's first stage contributor (the
  /// second family: AppendStageContributorDofs; AddDynamicGradient,
  /// AddDynamicBlock).
  int firstStageContributor = 0;
};

/// The step the line search accepted: q ← q_saved ⊕ α δ (δ in global DoF
/// order); with `corrected`, the step was δ + δc of a second-order correction
/// and `delta` is the last δc (α = 1).
struct AcceptedStep {
  Span<real const> delta;
  real alpha = 1;
  bool corrected = false;
};

/// The DoF lists of the stage contributors (StageTerm::
/// AppendStageContributorDofs), their storage kept from one stage to the
/// next so that a stage start allocates nothing once the lists have grown to
/// their size: Add() gives the next list, empty.
class StageDofLists {
 public:
  void Clear() { size_ = 0; }
  DynamicArray<int>& Add() {
    if (size_ == lists_.size()) lists_.emplace_back();
    DynamicArray<int>& list = lists_[size_++];
    list.clear();
    return list;
  }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  DynamicArray<int> const& operator[](std::size_t i) const { return lists_[i]; }
  /// The lists added since Clear().
  Span<DynamicArray<int> const> Lists() const { return {lists_.data(), size_}; }

 private:
  DynamicArray<DynamicArray<int>> lists_;
  std::size_t size_ = 0;
};

/// A contributor to a stage's incremental potential.
///
/// Order of calls: at each pattern build AppendContributorDofs (after the
/// own-block choices, below) and ReserveThreads; per stage BeginStage (every
/// term, at the committed configuration, before any DoF owner moves to its
/// first iterate) and AppendStageContributorDofs, then per Newton iteration
/// AddGradientAndHessian and, in
/// the line search, AddEnergy at trial configurations, AcceptStep after an
/// accepted step; EndStage at the converged configuration.
///
/// Contributors: a term adds `n` contributors, numbered from the
/// `firstContributor` the solver passes. Each contributor adds at most one
/// gradient and one block per assembly, and skips itself where
/// !assembler.Evaluates(c); its energy is counted where assembler.Owns(c)
/// (both always true in one process; docs/distributed.md).
class StageTerm {
 public:
  virtual ~StageTerm() = default;

  /// The DoF lists (global indices) of this term's contributors, appended in
  /// a fixed order: its stencil.
  virtual void AppendContributorDofs(DynamicArray<DynamicArray<int>>& dofLists) const = 0;
  /// Sizes per-thread scratch for `numThreads` assembly threads (at each
  /// pattern build and thread-count change; the default has none).
  virtual void ReserveThreads(int /*numThreads*/) {}
  /// Contributors whose DoF lists change between stages (contact pairs: the
  /// second family of HessianAssembler): their DoF lists for this stage,
  /// appended after BeginStage (each StageDofLists::Add). The default has
  /// none.
  virtual void AppendStageContributorDofs(StageDofLists& /*dofLists*/) const {}

  /// Prepares the stage from the committed configuration.
  virtual void BeginStage(StageContext const& stage) = 0;
  /// Adds this term's energy at the current iterate to `sum`, one
  /// EnergySum::Add per energy in a fixed order, of the contributors this
  /// process owns (assembler.Owns). The round-off scale of an energy made of
  /// differences of poses, or of parts that cancel, is what eps times bounds
  /// its round-off beyond eps |E| (an articulated actor's).
  virtual void AddEnergy(HessianAssembler const& assembler, int firstContributor, EnergySum& sum) const = 0;
  /// Adds the energy gradient and the Hessian blocks of its contributors
  /// through the assembler (AddGradient, AddBlock; loops over many
  /// contributors on assembler.ParallelFor). Without `projectHessian` blocks
  /// may be exact and indefinite (the solver then retries projected).
  virtual void AddGradientAndHessian(HessianAssembler& assembler, int firstContributor,
                                     AssemblyOptions const& options) const = 0;
  /// After the line search accepted a step (force estimates of
  /// constraints: docs/architecture.md, "Newton").
  virtual void AcceptStep(AcceptedStep const& /*step*/) {}
  /// Whether this term takes part in second-order corrections (below).
  virtual bool HasSecondOrderCorrection() const { return false; }
  /// At a trial configuration q + δ (`step` = δ): adds to `gradient` the
  /// force of the term's second-order error along δ, Jᵀ (f(g(q + δ)) −
  /// f(g + J δ)) with J of the last assembly (a second-order correction's
  /// right-hand side).
  virtual void AddCorrectionForce(Span<real const> /*step*/, Span<real> /*gradient*/) {}
  /// The safe-step hook, for terms that bound Newton's steps (BoundsSteps):
  /// the largest α' <= alpha such that the whole move from the current
  /// configuration to q ⊕ α' δ keeps this term valid (collision detection:
  /// no surfaces pass through each other on the way). The solver asks it with
  /// the DoF owners at the saved iterate, before it moves them, and never
  /// tries a step beyond the smallest answer. The default: alpha.
  virtual bool BoundsSteps() const { return false; }
  virtual real LargestSafeStep(Span<real const> /*delta*/, real alpha) const { return alpha; }
  /// For a term that bounds steps: whether the move from the stage start
  /// (the configuration at BeginStage) to Newton's first iterate keeps it
  /// valid. When a term refuses, every DoF owner starts the stage from the
  /// stage start instead (an inertial prediction through an obstacle).
  virtual bool AcceptsFirstIterate() const { return true; }
  /// For a term that bounds steps by a region found at the stage start (the
  /// contact candidates within each vertex's displacement bound): after an
  /// accepted Newton step, when the iterate has come near that region's edge,
  /// the region is found again around the current iterate and true is
  /// returned: its stage contributors may have changed (the solver sets them
  /// again). Each term it keeps stays the same function of the DoFs, and a
  /// term it adds is zero at the current iterate, so Eᵢ does not change.
  /// The default: never.
  virtual bool RecenterStepBounds() { return false; }
  /// A term that bounds steps may offer the line search a second direction
  /// where the step along δ was cut short: δ with each of its DoFs' shares
  /// scaled down to the fraction that is safe for that share alone (a
  /// contact's vertex stopped at its own time of impact, the rest moving
  /// on). Called at the saved iterate; the line search then asks
  /// LargestSafeStep of the result as of any step. The default: δ as it is.
  virtual void LimitStepPerDof(Span<real> /*delta*/) const {}
  /// A term with a target of its own within the stage (a kinematic
  /// obstacle's pose at the stage end): whether it is there. Newton
  /// converges only where every term is. While a term is short of its
  /// target, each Newton iteration moves it along with the DoF owners: its
  /// assembly adds to the gradient the linear response to the rest of its
  /// way (the step then carries the bodies it pushes along), its
  /// LargestSafeStep covers its own motion over the same fraction α of that
  /// way, and AdvanceTarget(α) moves it there from the current
  /// configuration — false, and nothing moved, where that would leave it
  /// invalid (the solver then halves α). The default: always there.
  virtual bool AtTarget() const { return true; }
  virtual bool AdvanceTarget(real /*fraction*/) { return true; }
  /// Commits the converged stage.
  virtual void EndStage() = 0;

  /// The own-block solve this term offers (an articulated actor on its
  /// tree), or nullptr: stage/own_block_solve.h.
  virtual OwnBlockSolve* GetOwnBlockSolve() { return nullptr; }
  /// Contributor `k` (counted from this term's first) as a term on an
  /// articulated link that an own-block solve can take in, or nullptr.
  virtual LinkTerm* GetLinkTerm(int /*k*/) { return nullptr; }
};

/// An owner of a contiguous block of the configuration's DoFs (an actor).
/// The solver moves it along Newton steps; the term it also is (StageTerm)
/// prices where it stands.
class StageDofs {
 public:
  virtual ~StageDofs() = default;

  virtual int GetNumDofs() const = 0;
  /// First global DoF index: its DoFs are [offset, offset + n).
  virtual int GetDofOffset() const = 0;
  /// Sizes of the DoF blocks that form one vertex each in the ordering graph
  /// (one block of 6 for a rigid body, one of 3 per deformable node, ...).
  virtual void AppendDofBlockSizes(DynamicArray<int>& sizes) const = 0;
  /// Writes its rows [offset, offset + n) of the scene's rigid-body modes at
  /// the current configuration: `modes` is numDofs × 6, columns the world
  /// translations along x, y, z and the infinitesimal world rotations about
  /// the x, y, z axes through the origin, in its DoFs (the near-null space of
  /// elasticity for AMG). The default leaves them zero.
  virtual void WriteRigidBodyModes(Eigen::Ref<MatrixX> /*modes*/) const {}
  /// Writes its entries [offset, offset + n) of the DoF length scales ℓⱼ [m
  /// per DoF unit] with which Newton judges a step as a velocity of material
  /// points: 1 for displacements; a rigid body's rotations its rms radius.
  virtual void WriteDofLengthScales(Span<real> scales) const = 0;
  /// Writes its entries [offset, offset + n) of a diagonal estimate of its
  /// inverse mass, 1/M_jj [1/kg or 1/(kg·m²)], at the current configuration
  /// (the near-rigid cap: NewtonParams::nearRigidBeta). Exact where M is
  /// diagonal; elsewhere the Jacobi estimate.
  virtual void WriteDofInverseMasses(Span<real> inverseMasses) const = 0;

  /// Moves to Newton's first iterate of the stage (after every term's
  /// BeginStage): its inertial prediction, or the stage start.
  virtual void MoveToFirstIterate() {}
  /// Saves the current iterate; RestoreIterate returns to it (line search).
  virtual void SaveIterate() = 0;
  virtual void RestoreIterate() = 0;
  /// q ← saved iterate ⊕ α·δ, δ read from the global increment vector.
  virtual void ApplyIncrementFromSaved(Span<real const> delta, real alpha) = 0;
  /// True when every configuration value is finite.
  virtual bool IsStateFinite() const = 0;
};

}  // namespace superdex::internal

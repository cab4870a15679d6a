// Actor: an owner of a contiguous range of generalized DoFs in the scene's
// configuration (design.md §3). The public part is identity and introspection;
// the stage solver drives the dynamics through the internal interface below.
#pragma once

#include <memory>

#include <superdex/assembly/owned_contributors.h>
#include <superdex/core/handle.h>
#include <superdex/core/types.h>

namespace superdex {

class Scene;
class Constraint;
enum class ConstraintHessian;

enum class ActorType { Rigid, Deformable, Rod, Articulated };

std::string_view ToString(ActorType type);

namespace internal {
class StageSolver;
struct StageCoefficients;
class HessianAssembler;
struct ActorTestAccess;  // defined by white-box tests only

/// Opaque copy of an actor's complete dynamic state (configuration,
/// velocities, integrator history), for transactional steps.
struct ActorSnapshot {
  virtual ~ActorSnapshot() = default;
};

/// The snapshot of an actor whose whole dynamic state is one copyable State.
template <class State>
struct StateSnapshot final : ActorSnapshot {
  State state;
};

/// Copies `state` into `snapshot`, allocating it on first use only.
template <class State>
void SaveStateSnapshot(State const& state, std::unique_ptr<ActorSnapshot>& snapshot) {
  auto* own = dynamic_cast<StateSnapshot<State>*>(snapshot.get());
  if (!own) {
    snapshot = std::make_unique<StateSnapshot<State>>();
    own = static_cast<StateSnapshot<State>*>(snapshot.get());
  }
  own->state = state;
}

template <class State>
void RestoreStateSnapshot(ActorSnapshot const& snapshot, State& state) {
  state = static_cast<StateSnapshot<State> const&>(snapshot).state;
}
}  // namespace internal

class Actor {
 public:
  virtual ~Actor() = default;
  Actor(Actor const&) = delete;
  Actor& operator=(Actor const&) = delete;

  ActorHandle GetHandle() const { return handle_; }
  ActorType GetType() const { return type_; }
  /// Number of generalized DoFs (6 for a rigid body).
  int GetNumDofs() const { return numDofs_; }
  /// First global DoF index of this actor; its DoFs are [offset, offset + n).
  /// Global indices change when actors created before it are destroyed.
  int GetDofOffset() const { return dofOffset_; }

 protected:
  Actor(ActorType type, int numDofs) : type_(type), numDofs_(numDofs) {}

  // ---- internal interface, driven by the scene and the stage solver ----
  friend class Scene;
  friend class internal::StageSolver;
  friend struct internal::ActorTestAccess;

  /// Sizes of the DoF blocks that form one vertex each in the ordering graph
  /// (one block of 6 for a rigid body, one of 3 per deformable node, ...).
  virtual void AppendDofBlockSizes(DynamicArray<int>& sizes) const = 0;
  /// Number of Hessian contributors this actor adds and their DoF lists
  /// (global indices), appended in a fixed order.
  virtual void AppendContributorDofs(DynamicArray<DynamicArray<int>>& dofLists) const = 0;
  /// Writes this actor's rows [offset, offset + n) of the scene's rigid-body
  /// modes at the current configuration: `modes` is numDofs × 6, columns the
  /// world translations along x, y, z and the infinitesimal world rotations
  /// about the x, y, z axes through the origin, expressed in each actor's
  /// DoFs (the near-null space of elasticity for AMG). The default leaves the
  /// rows untouched (zero: DoFs without a rigid-body meaning).
  virtual void WriteRigidBodyModes(Eigen::Ref<MatrixX> /*modes*/) const {}

  /// Writes this actor's entries [offset, offset + n) of the DoF length
  /// scales ℓⱼ [m per DoF unit] with which Newton judges a step as a velocity
  /// of material points: 1 for displacements; a rigid body's rotations its rms
  /// radius. The default writes 1.
  virtual void WriteDofLengthScales(Span<real> scales) const;

  /// Writes this actor's entries [offset, offset + n) of a diagonal estimate
  /// of its inverse mass, 1/M_jj with M the actor's mass matrix (the Hessian
  /// of its kinetic energy in its DoF increments) at the current
  /// configuration [1/kg or 1/(kg·m²)]: a rigid body 1/m for its
  /// translations and 1/(R I_b Rᵀ)_jj for its world-frame rotations; a
  /// deformable or rod node 1/mᵢ for its displacement (and a rod node
  /// 1/(twist inertia) for its twist); an articulated actor 1/M(q)_jj, the
  /// diagonal of its joint-space mass matrix (armature included). Exact
  /// where M is diagonal; elsewhere the Jacobi estimate (at most diag(M⁻¹)).
  /// The stage solver calls it once per stage, at the committed
  /// configuration, for the near-rigid cap (NewtonParams::nearRigidBeta).
  virtual void WriteDofInverseMasses(Span<real> inverseMasses) const = 0;

  /// Prepares a stage from the committed state: start configuration,
  /// inertial target and weight (from the integrator coefficients). An actor
  /// without history yet (its first step) uses backward Euler's coefficients.
  virtual void BeginStage(internal::StageCoefficients const& stage, Real3 const& gravity) = 0;
  /// Inertia + gravity (+ internal elastic) energy at the current iterate,
  /// of the contributors `owned` says this rank counts (in
  /// AppendContributorDofs's order): the whole energy when it is empty, as
  /// in one process. Across MPI ranks each rank counts its own contributors
  /// and the stage solver adds the ranks' sums (docs/distributed.md).
  virtual real Energy(internal::OwnedContributors owned) const = 0;
  /// The magnitude the round-off of the last Energy scales with beyond |E|
  /// itself (energy units; eps times it bounds that round-off): an energy
  /// made of differences of poses, or of terms that cancel, resolves
  /// changes far coarser than eps |E|. The stage solver adds it to Σ|terms|
  /// for the resolution of Eᵢ (its line search's allowance and its
  /// round-off stall test). 0: |E| is the scale.
  virtual real EnergyRoundOffScale() const { return 0; }
  /// Adds the energy gradient and the Hessian blocks through the assembler
  /// (AddGradient, AddBlock: at most one of each per contributor),
  /// contributors starting at `firstContributor`; loops over many elements
  /// run on assembler.ParallelFor. With `projectHessian` every block is PSD (element
  /// Hessians projected); without it elastic element blocks are exact and may
  /// be indefinite (the stage solver falls back to projection when the
  /// assembled matrix is not positive definite).
  virtual void AddGradientAndHessian(internal::HessianAssembler& assembler,
                                     int firstContributor, bool projectHessian) const = 0;
  // ---- own-block solves (articulated actors: an O(N) recursion over the
  // tree instead of a dense block in the scene's matrix; docs/articulated.md) ----
  /// True when the actor can solve its own Newton block. Its DoFs then fall
  /// into groups (an articulated actor's joints): other contributors may add
  /// to one group's diagonal block of the actor's DoFs, and to nothing else.
  virtual bool CanSolveOwnBlock() const { return false; }
  /// The group of local DoF `dof` (CanSolveOwnBlock actors).
  virtual int GetDofGroup(int /*dof*/) const { return 0; }
  /// Set by the stage solver before AppendContributorDofs: with it the actor
  /// adds one contributor per group (that group's diagonal block) and keeps
  /// the coupling between groups to itself.
  void SetSolvesOwnBlock(bool solves) { solvesOwnBlock_ = solves; }
  bool SolvesOwnBlock() const { return solvesOwnBlock_; }
  /// After an assembly (SolvesOwnBlock actors): reads its groups' assembled
  /// diagonal blocks, which hold the other contributors' terms too,
  /// factorizes its block (with `projectHessian` made positive definite,
  /// pivot by pivot) and overwrites those blocks in the assembled matrix
  /// with the identity, so that the scene's solver returns −∇E on its DoFs,
  /// which SolveOwnBlock then replaces. False when the block is not positive
  /// definite (or not finite); with `projectHessian`, where that failure is
  /// final, `reason` says why (without, the stage solver retries projected).
  /// With `separateCouplings` a block coupled with other DoFs is made
  /// positive definite without its couplings' terms, which then join it: the
  /// Schur complement is then positive definite wherever those terms are.
  virtual bool FactorizeOwnBlock(internal::HessianAssembler& /*assembler*/, int /*firstContributor*/,
                                 bool /*projectHessian*/, bool /*separateCouplings*/, std::string& /*reason*/) {
    return true;
  }
  /// delta ← (own block)⁻¹ rhs on the actor's DoFs (global vectors), with
  /// the last FactorizeOwnBlock. Where the block is coupled to other DoFs
  /// (HasOwnBlockCoupling), delta holds the scene's solution on them (x_o)
  /// and the actor's part is A⁻¹(rhs_t − Cᵀ x_o).
  virtual void SolveOwnBlock(Span<real const> /*rhs*/, Span<real> /*delta*/) {}
  /// True where a folded constraint couples the actor's own block A with
  /// other bodies' DoFs (C): FactorizeOwnBlock then adds −C A⁻¹ Cᵀ to their
  /// block in the scene's matrix (a Schur complement), and
  /// EliminateOwnBlockFromRhs turns the scene's right-hand side −∇E
  /// (natural order, global) into the complement's, rhs_o − C A⁻¹ rhs_t.
  virtual bool HasOwnBlockCoupling() const { return false; }
  virtual void EliminateOwnBlockFromRhs(Span<real> /*rhs*/) {}
  /// A constraint on a part of this actor (an articulated link), alone or
  /// with a body of another actor that is not such a part, taken into the
  /// actor's own block (SolvesOwnBlock actors): the actor then assembles it
  /// (a coupling through its Schur complement), and the scene's matrix
  /// holds no block of it but over the other body's DoFs.
  /// False where the actor cannot take it. Set by the stage solver at each
  /// pattern build, after ClearFoldedConstraints.
  virtual bool FoldConstraint(Constraint* /*constraint*/) { return false; }
  virtual void ClearFoldedConstraints() {}
  /// The scene's constraint Hessian for the folded constraints (each stage).
  virtual void SetFoldedConstraintHessian(ConstraintHessian /*hessian*/) {}

  /// Saves the current iterate; RestoreIterate returns to it (line search).
  virtual void SaveIterate() = 0;
  virtual void RestoreIterate() = 0;
  /// q ← saved iterate ⊕ α·δ, δ read from the global increment vector.
  virtual void ApplyIncrementFromSaved(Span<real const> delta, real alpha) = 0;
  /// True when every configuration value is finite.
  virtual bool IsStateFinite() const = 0;
  /// Commits the converged stage: velocities and integrator history.
  virtual void EndStage() = 0;

  /// Copies the complete dynamic state into `snapshot` (allocated on first
  /// use, reused afterwards); RestoreSnapshot puts it back bit for bit.
  virtual void SaveSnapshot(std::unique_ptr<internal::ActorSnapshot>& snapshot) const = 0;
  virtual void RestoreSnapshot(internal::ActorSnapshot const& snapshot) = 0;

  ActorHandle handle_;
  ActorType type_;
  int numDofs_;
  int dofOffset_ = 0;
  bool solvesOwnBlock_ = false;
};

}  // namespace superdex

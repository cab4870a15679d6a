// Internal: Newton's method on one stage's incremental potential
//
//   Eᵢ(q) = ½ w ‖q ⊖ q̂ᵢ‖²_M + U(q) + Σ Φᶜᵢ(q)
//
// assembled into the cached pattern, solved by the scene's linear solver,
// with a backtracking (Armijo) line search on Eᵢ and a convergence test on
// the step as a velocity of material points, or on a Newton decrement below
// the round-off resolution of Eᵢ. Owns every per-iteration buffer: after
// Analyze, a Newton iteration allocates nothing.
#pragma once

#include <chrono>
#include <memory>

#include <superdex/assembly/hessian_assembler.h>
#include <superdex/constraints/constraint.h>
#include <superdex/core/error.h>
#include <superdex/linsolve/linear_solver.h>
#include <superdex/linsolve/reused_factor_cg.h>
#include <superdex/scene/collectives.h>
#include <superdex/scene/scene_params.h>

namespace superdex {
class Actor;
}

namespace superdex::internal {

/// Test hook: make the linear solve of a given Newton iteration fail.
struct FaultInjection {
  int failLinearSolveAtIteration = -1;  ///< 1-based; -1 disables
};

class StageSolver {
 public:
  /// Rebuilds pattern, ordering and slot tables for the given topology, and
  /// sizes all workspaces. Returns false (nothing changed) on failure.
  bool Analyze(DynamicArray<Actor*> const& actors, DynamicArray<Constraint*> const& constraints,
               OrderingMethod ordering, SceneStats& stats, Error& error);

  /// The ranks the stages run on (SceneParams::communicator), before the
  /// first Analyze: with more than one, each rank assembles its part of the
  /// rows and the linear solver runs across the ranks (docs/distributed.md).
  void SetCommunicator(Communicator const& communicator);
  bool IsDistributed() const { return numRanks_ > 1; }

  /// Threads of the assembly (SceneParams::numThreads: 0 = every CPU this
  /// process may use); the assembled values do not depend on it.
  void SetNumThreads(int numThreads);
  int GetNumThreads() const { return executor_.GetNumThreads(); }

  /// Chooses the backend (kAuto resolves by size) and the PCG settings
  /// (validated); the new backend analyzes the cached pattern lazily at the
  /// next solve. Returns false (nothing changed) on invalid input.
  bool SetLinearSolver(LinearSolverType type, PcgParams const& pcg, Error& error);

  /// Runs Newton on one stage. On failure `error` names the stage, the
  /// Newton iteration and the cause; actors are left at some iterate (the
  /// caller restores its snapshot).
  bool Solve(int stageIndex, StageCoefficients const& stage, DynamicArray<Actor*> const& actors,
             DynamicArray<Constraint*> const& constraints, Real3 const& gravity,
             NewtonParams const& newton, SceneStats& stats, Error& error);

  void SetFaultInjection(FaultInjection const& fault) { fault_ = fault; }
  HessianAssembler const& GetAssembler() const { return assembler_; }
  LinearSolver const* GetLinearSolver() const { return solver_.get(); }

 private:
  void ReserveThreadWorkspaces();
  /// Actor::SetSolvesOwnBlock for each actor (before its contributor lists).
  void ChooseOwnBlockSolves(DynamicArray<Actor*> const& actors,
                            DynamicArray<Constraint*> const& constraints) const;
  /// Actor::FactorizeOwnBlock for those actors, after an assembly (timed as
  /// factorization in `stats`); NotPositiveDefinite when one fails.
  LinearSolveResult FactorizeOwnBlocks(bool project, bool separateCouplings, SceneStats& stats);
  /// Their parts of delta_ from −gradient_, after the matrix's solve.
  void SolveOwnBlocks();
  /// Factorizes the assembled matrix (counted and timed in `stats`).
  LinearSolveResult FactorizeMatrix(SceneStats& stats);
  /// Across ranks: every rank's owned entries of gradient_ to every rank.
  void GatherGradient();
  real TotalEnergy(DynamicArray<Actor*> const& actors, DynamicArray<Constraint*> const& constraints,
                   real h);
  bool EnsureSolverReady(DynamicArray<Actor*> const& actors, SceneStats& stats, Error& error);
  /// H δ = −∇E with the current factorization/set-up: permutes the gradient,
  /// solves, permutes δ back; adds the solve time and iterations to `stats`.
  LinearSolveResult SolveNewtonSystem(SceneStats& stats, bool resume = false);
  /// orderedRhs_ = −∇E in the fill-reducing order (both solve paths); where
  /// an actor's own block is coupled, the Schur complement's right-hand side.
  void OrderNewtonRhs();
  /// NewtonParams::reuseFactorization: solves H δ = −∇E by CG preconditioned
  /// with the direct solver's last factorization (of an earlier matrix).
  /// True, with δ in delta_, when that CG converged; false when reuse does
  /// not apply or did not pay (the caller factorizes).
  /// To the relative residual `tolerance`; with `resume`, continuing the
  /// last such solve (same right-hand side) from its solution.
  bool SolveWithReusedFactor(NewtonParams const& newton, real tolerance, bool resume,
                             SceneStats& stats);
  /// The most CG iterations a reused factorization may take: the iterations
  /// that cost one numeric factorization, by the factor's flop counts.
  int ReuseIterationCap() const;
  /// A solve Newton can step with: converged, or truncated at the PCG cap
  /// with PcgParams::truncatedSteps on.
  bool Usable(LinearSolveResult const& result) const;
  /// True (and counted) when `result` is a truncated solve whose step
  /// delta_ descends.
  bool TakeTruncated(LinearSolveResult const& result, SceneStats& stats) const;
  /// The inexact-Newton forcing term for this iteration (Eisenstat–Walker
  /// choice 2, safeguarded) in [tightest, loosest], from the gradient norms
  /// of this and the last iteration; `iteration` is 1-based.
  real ForcingTerm(int iteration, real gradientNorm, real tightest, real loosest);
  /// maxⱼ ℓⱼ |δⱼ| / h: the step as a velocity of material points (ℓⱼ the
  /// DoF length scales of the actors).
  real ScaledStepNorm(real h) const;
  /// The round-off resolution of Eᵢ: kRoundOffUlps ulps of energyScale_.
  real Resolution() const;
  bool SecondOrderCorrection(DynamicArray<Actor*> const& actors,
                             DynamicArray<Constraint*> const& constraints, real h, real energy,
                             real slope, SceneStats& stats, real& trialEnergy);

  ParallelExecutor executor_;
  HessianAssembler assembler_;
  LinearSolverType requestedSolver_ = LinearSolverType::Auto;
  PcgParams pcg_;
  OrderingMethod ordering_ = OrderingMethod::Metis;
  real previousGradientNorm_ = 0, previousForcingTerm_ = 0;
  MatrixX nearNullSpace_;  ///< rigid-body modes (AMG), rebuilt with the pattern
  std::unique_ptr<LinearSolver> solver_;
  ConstraintWorkspace constraintWorkspace_;
  DynamicArray<ConstraintWorkspace> threadWorkspaces_;  ///< one per assembly thread
  int maxConstraintDimension_ = 1, maxConstraintDofs_ = 1;
  DynamicArray<int> firstContributor_;  ///< per actor, then per constraint
  DynamicArray<Actor*> ownBlockActors_;  ///< the actors that solve their own blocks
  DynamicArray<int> ownBlockContributors_;  ///< and their first contributors
  VectorX ownBlockRhs_;  ///< −∇E for their solves (natural order)
  /// some own block is coupled with other DoFs (Actor::HasOwnBlockCoupling):
  /// the right-hand side of the Schur complement (natural order) in schurRhs_
  bool ownBlocksCoupled_ = false;
  /// every actor solves its own block, uncoupled: the scene's matrix is the
  /// identity, its factorization and solve skipped (δ = −∇E, then the blocks')
  bool identityMatrix_ = false;
  VectorX schurRhs_;
  VectorX gradient_, delta_, orderedRhs_, orderedSolution_;
  VectorX newtonStep_, correctedStep_;  ///< δ and δ + Σ δc in a second-order correction
  VectorX dofLengthScales_;  ///< ℓⱼ per DoF (Actor::WriteDofLengthScales)
  VectorX dofInverseMasses_;  ///< 1/M_jj per DoF (Actor::WriteDofInverseMasses), near-rigid cap only
  ReusedFactorCg reuseCg_;
  VectorX orderedLengthScales_;  ///< dofLengthScales_ in the fill-reducing order
  ReusedFactorCg::StepTolerance reuseStepTolerance_;  ///< over orderedLengthScales_, per stage
  int reuseFailuresInRow_ = 0;  ///< reused-factor solves that did not converge, this stage
  std::int64_t hessianNonzeros_ = 0;  ///< of the whole pattern (SceneStats::hessianNonzeros)
  real energyScale_ = 0;     ///< Σ(|terms| + round-off scales) of Eᵢ at the last TotalEnergy
  FaultInjection fault_;
  // across MPI ranks (IsDistributed)
  Communicator communicator_;
  int numRanks_ = 1, rank_ = 0;
  VectorX orderedGradient_;                  ///< gradient_ in the partition-major order
  OwnedRowsProduct ownedRowsProduct_;        ///< reuseCg_'s product
  DynamicArray<int> rankCounts_, rankDisplacements_;  ///< MPI_Allgatherv scratch
  DynamicArray<real> rankSums_;  ///< SumInRankOrder scratch: 2 per rank
};

}  // namespace superdex::internal

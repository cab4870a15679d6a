// NewtonSolver: Newton's method on one stage's incremental potential
//
//   Eᵢ(q) = Σ_terms Eₜ(q)      (stage/stage_term.h)
//
// assembled into the cached pattern, solved by the scene's linear solver,
// with a backtracking line search bounded by the terms' safe steps and a
// convergence test on the step as a velocity of material points, or on a
// Newton decrement below Eᵢ's round-off resolution (docs/architecture.md,
// "Newton").
//
// The loop (Solve) is a list of named parts, each owning its state:
//   StageProblem         the terms and DoF owners (begin, energy, assembly, moves)
//   OwnBlockElimination  terms that solve their own block (an articulated tree)
//   LinearStep           H δ = −∇E: direct, reused-factor CG, PCG, truncated
//   ConvergenceTest      the scaled step norm and the round-off stall; Eᵢ
//   LineSearch           backtracking, second-order correction, expansion
//   RankGroup            the distributed pieces (docs/distributed.md)
// After Analyze, a Newton iteration allocates nothing.
#pragma once

#include <superdex/assembly/hessian_assembler.h>
#include <superdex/core/error.h>
#include <superdex/core/parallel.h>
#include <superdex/linsolve/linear_solver.h>
#include <superdex/solver/newton_params.h>
#include <superdex/solver/scene_stats.h>
#include <superdex/solver/collectives.h>
#include <superdex/solver/convergence_test.h>
#include <superdex/solver/line_search.h>
#include <superdex/solver/linear_step.h>
#include <superdex/solver/own_block_elimination.h>
#include <superdex/solver/stage_problem.h>

namespace superdex::internal {

/// Test hook: make the linear solve of a given Newton iteration fail.
struct FaultInjection {
  int failLinearSolveAtIteration = -1;  ///< 1-based; -1 disables
};

class NewtonSolver {
 public:
  NewtonSolver();
  NewtonSolver(NewtonSolver const&) = delete;
  NewtonSolver& operator=(NewtonSolver const&) = delete;

  /// Rebuilds pattern, ordering and slot tables for the DoF owners (in DoF
  /// order) and terms (in contributor order), chooses the own-block solves,
  /// and sizes every workspace. False (and `error`) on failure.
  bool Analyze(DynamicArray<StageDofs*> dofs, DynamicArray<StageTerm*> terms, OrderingMethod ordering,
               SceneStats& stats, Error& error);

  /// The ranks the stages run on (SceneParams::communicator), before the
  /// first Analyze: with more than one, each rank assembles its part of the
  /// rows and the linear solver runs across the ranks (docs/distributed.md).
  void SetCommunicator(Communicator const& communicator);
  bool IsDistributed() const { return ranks_.IsDistributed(); }
  int GetNumRanks() const { return ranks_.GetSize(); }
  /// The first of `values` on which the ranks differ, or -1 (always -1 in
  /// one process): a collective call's arguments checked before it acts.
  int FirstRankDisagreement(Span<std::uint64_t const> values) { return ranks_.FirstDisagreement(values); }
  /// Drops the terms and DoF owners of the last Analyze (the scene's
  /// topology changed: some may be destroyed) until the next Analyze.
  void ForgetTerms() { problem_.Set({}, {}); }
  /// Threads of the assembly (SceneParams::numThreads: 0 = every CPU this
  /// process may use); the assembled values do not depend on it.
  void SetNumThreads(int numThreads);
  int GetNumThreads() const { return executor_.GetNumThreads(); }
  /// Chooses the backend (Auto resolves by size) and the PCG settings; the
  /// new backend analyzes the cached pattern lazily at the next solve. False
  /// (nothing changed) on invalid input.
  bool SetLinearSolver(LinearSolverType type, PcgParams const& pcg, Error& error) {
    return linear_.SetLinearSolver(type, pcg, error);
  }

  /// Runs Newton on one stage (stage.inverseMasses is filled here). On
  /// failure `error` names the stage, the Newton iteration and the cause;
  /// the DoF owners are left at some iterate (the caller restores them).
  bool Solve(int stageIndex, StageContext stage, NewtonParams const& newton, SceneStats& stats, Error& error);

  /// How the pattern follows the terms' stage contributors (SceneParams::patternPolicy).
  void SetPatternPolicy(PatternPolicy policy) { patternPolicy_ = policy; }
  void SetFaultInjection(FaultInjection const& fault) { fault_ = fault; }
  HessianAssembler const& GetAssembler() const { return assembler_; }
  LinearSolver const* GetLinearSolver() const { return linear_.GetBackend(); }

 private:
  /// Every term's BeginStage (with the near-rigid cap's inverse masses), the
  /// stage contributors and the pattern they need, the linear solver for it,
  /// the first iterates, the length scales of the convergence test.
  bool BeginStage(StageContext& stage, NewtonParams const& newton, SceneStats& stats, Error& error);
  /// The terms' contributors of this stage (the assembler's second family):
  /// their slots, the pattern grown where they need entries it lacks.
  bool SetStageContributors(SceneStats& stats, Error& error);
  /// The split of the last pattern build into `stats`.
  void AddAnalysisTimes(SceneStats& stats) const;
  /// Assembles ∇E and H and solves for δ, retrying the iteration projected
  /// where the exact matrix is indefinite (`projected` says which ran), with
  /// a shifted diagonal where a projected one fails by round-off. False with
  /// `error` on a non-finite gradient; the solve's result in `result`.
  /// Moves the iterate along δ and every term short of its stage target
  /// towards it by the same fraction, as far as they stay valid.
  void MoveWithTargets();
  bool ComputeStep(int stageIndex, int iteration, NewtonParams const& newton, SceneStats& stats,
                   LinearSolveResult& result, bool& projected, Error& error);
  bool LinearSolverFailed(int stageIndex, int iteration, LinearSolveResult const& failed, Error& error) const;

  ParallelExecutor executor_;
  HessianAssembler assembler_;
  RankGroup ranks_;
  StageProblem problem_;
  OwnBlockElimination ownBlocks_;
  LinearStep linear_;
  ConvergenceTest convergence_;
  LineSearch lineSearch_;
  VectorX gradient_, delta_;   ///< ∇E and δ, natural order
  StageDofLists stageDofs_;  ///< the stage contributors' DoF lists (storage kept)
  VectorX dofInverseMasses_;   ///< 1/M_jj per DoF (StageDofs::WriteDofInverseMasses), near-rigid cap only
  PatternPolicy patternPolicy_ = PatternPolicy::ReserveAndGrow;
  FaultInjection fault_;
};

}  // namespace superdex::internal

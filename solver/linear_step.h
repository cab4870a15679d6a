// LinearStep: Newton's step H δ = −∇E with the scene's backend, in the
// fill-reducing order of the cached pattern — a direct factorization
// (CHOLMOD, MUMPS, dense), CG preconditioned by the last factorization
// (NewtonParams::reuseFactorization, docs/linear_solvers.md "Reused
// factorizations"), or PETSc PCG with inexact-Newton forcing terms and
// truncated steps (docs/architecture.md, "Newton"). The own blocks
// (OwnBlockElimination) are factorized before the scene's matrix and solved
// after it.
//
// Owns the backend and every buffer of the solve; the gradient and the step
// are the Newton solver's (Bind). After Reserve nothing is allocated per
// iteration.
#pragma once

#include <cstdint>
#include <memory>

#include <superdex/assembly/hessian_assembler.h>
#include <superdex/linsolve/linear_solver.h>
#include <superdex/linsolve/reused_factor_cg.h>
#include <superdex/solver/collectives.h>
#include <superdex/solver/newton_params.h>
#include <superdex/solver/own_block_elimination.h>
#include <superdex/solver/scene_stats.h>

namespace superdex::internal {

class LinearStep {
 public:
  LinearStep(HessianAssembler& assembler, OwnBlockElimination& ownBlocks, RankGroup& ranks)
      : assembler_(assembler), ownBlocks_(ownBlocks), ranks_(ranks) {}
  /// The Newton solver's gradient (read) and step (written), natural order.
  void Bind(VectorX const* gradient, VectorX* delta) {
    gradient_ = gradient;
    delta_ = delta;
  }
  void SetExecutor(ParallelExecutor const* executor) { executor_ = executor; }

  /// Chooses the backend (Auto resolves by size) and the PCG settings
  /// (validated against the ranks); the new backend analyzes the cached
  /// pattern lazily at the next stage. False (nothing changed) on invalid input.
  bool SetLinearSolver(LinearSolverType type, PcgParams const& pcg, Error& error);
  /// Drops the backend (a new communicator: it is made again for the ranks).
  void ResetBackend() { solver_.reset(); }
  LinearSolver const* GetBackend() const { return solver_.get(); }
  PcgParams const& GetPcg() const { return pcg_; }

  /// At a pattern build: sizes the buffers; `hessianNonzeros` of the whole
  /// pattern (the reused-factor CG's cost model).
  void Reserve(int numDofs, OrderingMethod ordering, std::int64_t hessianNonzeros);
  /// The pattern's entries after it grew (the reused-factor CG's cost model).
  void SetHessianNonzeros(std::int64_t hessianNonzeros) { hessianNonzeros_ = hessianNonzeros; }
  /// Before a stage: the backend for the pattern, analyzed (once per pattern
  /// version; the rigid-body modes for AMG from `problem`).
  bool Prepare(StageProblem const& problem, SceneStats& stats, Error& error);
  /// At the stage start: the DoF length scales (natural order, for the
  /// reused-factor CG's step tolerance) and the stage's settings.
  void BeginStage(Span<real const> lengthScales, NewtonParams const& newton, real h);
  /// PCG with PcgParams::adaptiveTolerance: each iteration's tolerance is a
  /// forcing term.
  bool IsInexact() const { return solver_->IsIterative() && pcg_.adaptiveTolerance; }

  /// Once per Newton iteration (1-based), from ‖∇E‖₂: the inexact-Newton
  /// forcing term of the PCG solve, or of the reused-factor CG.
  void BeginIteration(int iteration, real gradientNorm, NewtonParams const& newton);
  /// δ after an assembly: the own blocks factorized, then a reused-factor CG
  /// or a factorization and solve. A failed own block is reported in the
  /// result (OwnBlocksFailed then tells it from the matrix's failure).
  LinearSolveResult Solve(bool project, bool separateCouplings, NewtonParams const& newton, SceneStats& stats);
  bool OwnBlocksFailed() const { return ownBlocksFailed_; }
  /// A projected matrix that failed its factorization by round-off: its
  /// diagonal shifted by 1e-8 |Hⱼⱼ|, then 100× more up to 1e-2, refactorized
  /// and solved each time (a Levenberg step; counted in stats).
  LinearSolveResult ShiftDiagonal(LinearSolveResult result, SceneStats& stats);
  /// H δ = −(the current gradient) with the current factorization or set-up
  /// (a second-order correction's solve, or a resumed one with `resume`).
  LinearSolveResult SolveWithCurrentMatrix(SceneStats& stats, bool resume = false);

  /// A solve Newton can step with: converged, or truncated at the PCG cap
  /// with PcgParams::truncatedSteps on.
  bool Usable(LinearSolveResult const& result) const;
  /// True (and counted) when `result` is a truncated solve whose step δ descends.
  bool TakeTruncated(LinearSolveResult const& result, SceneStats& stats) const;
  /// A step that looks converged (`looksConverged` judges δ and is called
  /// again after each refinement) but came from a looser solve than the
  /// full tolerance — a reused-factor CG at a forcing term, a PCG solve at a
  /// forcing term or truncated at its cap — is resumed from where it stopped
  /// at the full tolerance, while each resumption at least halves the
  /// residual. Returns false with the failed result in `result` when the
  /// backend fails; `truncated` says whether δ is still a truncated step,
  /// `keepGoing` that the loose step is taken but does not end Newton.
  template <class Judge>
  bool Refine(Judge&& looksConverged, NewtonParams const& newton, LinearSolveResult& result, bool& truncated,
              bool& keepGoing, SceneStats& stats);

 private:
  LinearSolveResult Factorize(SceneStats& stats);
  /// orderedRhs_ = −∇E in the fill-reducing order (both solve paths); where
  /// an own block is coupled, the Schur complement's right-hand side.
  void OrderRhs();
  /// NewtonParams::reuseFactorization: H δ = −∇E by CG preconditioned with
  /// the direct solver's last factorization (of an earlier matrix), to the
  /// relative residual `tolerance`; with `resume`, continuing the last such
  /// solve. True, with δ, when that CG converged; false when reuse does not
  /// apply or did not pay (the caller factorizes).
  bool SolveWithReusedFactor(NewtonParams const& newton, real tolerance, bool resume, SceneStats& stats);
  /// The most CG iterations a reused factorization may take: the iterations
  /// that cost one numeric factorization, by the factor's flop counts.
  int ReuseIterationCap() const;
  /// Eisenstat–Walker choice 2 (safeguarded) in [tightest, loosest].
  real ForcingTerm(int iteration, real gradientNorm, real tightest, real loosest);

  HessianAssembler& assembler_;
  OwnBlockElimination& ownBlocks_;
  RankGroup& ranks_;
  ParallelExecutor const* executor_ = nullptr;
  VectorX const* gradient_ = nullptr;
  VectorX* delta_ = nullptr;

  LinearSolverType requested_ = LinearSolverType::Auto;
  PcgParams pcg_;
  OrderingMethod ordering_ = OrderingMethod::Metis;
  std::unique_ptr<LinearSolver> solver_;
  MatrixX nearNullSpace_;  ///< rigid-body modes (AMG), rebuilt with the pattern
  std::int64_t hessianNonzeros_ = 0;
  VectorX orderedRhs_, orderedSolution_, schurRhs_;

  // this stage and iteration
  real forcingTerm_ = 0;       ///< the PCG tolerance of this iteration
  real reuseTolerance_ = 0;    ///< the reused-factor CG's tolerance of this iteration
  bool reusedLoose_ = false;   ///< δ came from a reused-factor CG looser than factorReuseTolerance
  bool ownBlocksFailed_ = false;
  real previousGradientNorm_ = 0, previousForcingTerm_ = 0;
  ReusedFactorCg reuseCg_;
  VectorX orderedLengthScales_;  ///< the DoF length scales in the fill-reducing order
  ReusedFactorCg::StepTolerance reuseStepTolerance_;  ///< over orderedLengthScales_, per stage
  int reuseFailuresInRow_ = 0;  ///< reused-factor solves that did not converge, this stage
};

template <class Judge>
bool LinearStep::Refine(Judge&& looksConverged, NewtonParams const& newton, LinearSolveResult& result,
                        bool& truncated, bool& keepGoing, SceneStats& stats) {
  keepGoing = false;
  bool converged = looksConverged();
  // a reused-factor step from a forcing term that looks converged is
  // continued to factorReuseTolerance; when that CG cannot finish, the loose
  // step is taken but does not end Newton (the next iteration solves again,
  // refactorizing after a few such failures)
  if (reusedLoose_ && converged) {
    if (SolveWithReusedFactor(newton, newton.factorReuseTolerance, /*resume=*/true, stats)) {
      converged = looksConverged();
    } else {
      keepGoing = true;
      converged = false;
    }
  }
  // resumed again while it stays truncated and each resumption at least
  // halves the residual (restarted CG still converges, more slowly)
  bool loose = truncated || (IsInexact() && forcingTerm_ > pcg_.relativeTolerance);
  while (loose && converged) {
    real const previousResidual = result.relativeResidual;
    if (IsInexact()) solver_->SetRelativeTolerance(pcg_.relativeTolerance);
    result = SolveWithCurrentMatrix(stats, /*resume=*/true);
    truncated = TakeTruncated(result, stats);
    if (!result.Ok() && !truncated) return false;
    converged = looksConverged();
    loose = truncated && result.relativeResidual <= 0.5 * previousResidual;
  }
  return true;
}

}  // namespace superdex::internal

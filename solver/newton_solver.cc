#include <superdex/solver/newton_solver.h>

#include <chrono>
#include <cmath>

#include <superdex/core/stopwatch.h>
#include <superdex/core/validate.h>
#include <superdex/linsolve/petsc_distributed_matrix.h>

namespace superdex::internal {

namespace {
using Clock = std::chrono::steady_clock;

std::string Where(int stageIndex, int iteration) {
  return "stage " + std::to_string(stageIndex) + ", Newton iteration " + std::to_string(iteration);
}

bool Fail(ErrorCode code, int stageIndex, int iteration, std::string const& why, Error& error) {
  error.Set(code, Where(stageIndex, iteration) + ": " + why);
  return false;
}
}  // namespace

NewtonSolver::NewtonSolver()
    : linear_(assembler_, ownBlocks_, ranks_),
      convergence_(problem_, assembler_, ranks_),
      lineSearch_(problem_, convergence_, linear_) {
  linear_.Bind(&gradient_, &delta_);
  linear_.SetExecutor(&executor_);
  lineSearch_.Bind(&gradient_, &delta_);
}

void NewtonSolver::SetCommunicator(Communicator const& communicator) {
  ranks_.Set(communicator);
  linear_.ResetBackend();
}

void NewtonSolver::SetNumThreads(int numThreads) {
  executor_.SetNumThreads(numThreads);
  assembler_.SetExecutor(&executor_);
  problem_.ReserveThreads(executor_.GetNumThreads());
}

bool NewtonSolver::Analyze(DynamicArray<StageDofs*> dofs, DynamicArray<StageTerm*> terms, OrderingMethod ordering,
                           SceneStats& stats, Error& error) {
  problem_.Set(std::move(dofs), std::move(terms));
  DynamicArray<StageTerm*> const& all = problem_.GetTerms();
  // the stencils of the terms without an own block decide which own blocks
  // stay on and what they take in; then the own blocks' stencils
  ownBlocks_.Reset(problem_, ranks_.IsDistributed());
  DynamicArray<DynamicArray<DynamicArray<int>>> termDofs(all.size());
  for (std::size_t t = 0; t < all.size(); ++t)
    if (!all[t]->GetOwnBlockSolve()) all[t]->AppendContributorDofs(termDofs[t]);
  ownBlocks_.Choose(problem_, termDofs);
  for (std::size_t t = 0; t < all.size(); ++t)
    if (all[t]->GetOwnBlockSolve()) all[t]->AppendContributorDofs(termDofs[t]);
  DynamicArray<int> blockSizes;
  DynamicArray<DynamicArray<int>> contributorDofs;
  problem_.FlattenPattern(termDofs, blockSizes, contributorDofs);
  for (DynamicArray<int> const& dofs : contributorDofs)
    if (static_cast<int>(dofs.size()) > kDenseSolverMaxUnknowns) {
      // (an articulated actor's dense block, where its tree solve is off)
      error.Set(ErrorCode::InvalidArgument,
                "a dense block of " + std::to_string(dofs.size()) + " DoFs (an articulated actor's, where it "
                "cannot solve on its tree: ArticulatedBlockSolve::Dense, constraints on more than one of its "
                "joints, or several ranks) is above kDenseSolverMaxUnknowns = " +
                    std::to_string(kDenseSolverMaxUnknowns) + " DoFs in the scene's matrix");
      return false;
    }
  int const numDofs = problem_.GetNumDofs();
  if (!assembler_.Analyze(numDofs, blockSizes, contributorDofs, ordering, error, ranks_.GetSize(), ranks_.GetRank()))
    return false;
  ownBlocks_.Prepare(problem_, ranks_.IsDistributed());
  problem_.ReserveThreads(executor_.GetNumThreads());
  ranks_.Reserve(numDofs);
  gradient_.setZero(numDofs);
  delta_.setZero(numDofs);
  dofInverseMasses_.setZero(numDofs);
  convergence_.Reserve(numDofs);
  lineSearch_.Reserve(numDofs);
  // the whole pattern's entries: each rank stores only its part of it
  std::int64_t hessianNonzeros = assembler_.CountOwnedColumnEntries();
  if (ranks_.IsDistributed()) {
    real count[1] = {static_cast<real>(hessianNonzeros)};  // exact below 2⁵³
    ranks_.SumInRankOrder(count);
    hessianNonzeros = static_cast<std::int64_t>(count[0]);
  }
  linear_.Reserve(numDofs, ordering, hessianNonzeros);
  stats.patternBuilds = assembler_.GetNumPatternBuilds();
  stats.numDofs = numDofs;
  stats.ranks = ranks_.GetSize();
  stats.ownedDofs = assembler_.GetOwnedRowEnd() - assembler_.GetOwnedRowBegin();
  stats.hessianNonzeros = hessianNonzeros;
  AddAnalysisTimes(stats);
  return true;
}

bool NewtonSolver::BeginStage(StageContext& stage, NewtonParams const& newton, SceneStats& stats, Error& error) {
  // terms first, at the committed configuration (the near-rigid cap reads
  // the inverse masses there; the linear solver's analysis the rigid-body
  // modes), then the first iterates
  stage.inverseMasses = Span<real const>(dofInverseMasses_.data(), dofInverseMasses_.size());
  if (newton.nearRigidBeta > 0)
    problem_.WriteDofInverseMasses(Span<real>(dofInverseMasses_.data(), dofInverseMasses_.size()));
  stage.nearRigidBeta = newton.nearRigidBeta;
  stage.constraintHessian = newton.constraintHessian;
  problem_.BeginStage(stage);
  if (!SetStageContributors(stats, error) || !linear_.Prepare(problem_, stats, error)) return false;
  problem_.MoveToFirstIterate();
  real const h = stage.coefficients.duration;
  convergence_.BeginStage(newton.velocityTolerance, h);
  linear_.BeginStage(convergence_.GetLengthScales(), newton, h);
  return true;
}

bool NewtonSolver::SetStageContributors(SceneStats& stats, Error& error) {
  stageDofs_.Clear();
  problem_.AppendStageContributorDofs(stageDofs_);
  stats.stageContributors = static_cast<int>(stageDofs_.size());
  if (stageDofs_.empty() && assembler_.GetNumDynamicContributors() == 0) return true;
  auto const start = Clock::now();
  HessianAssembler::DynamicUpdate update;
  if (!assembler_.SetDynamicContributors(stageDofs_.Lists(), update, error,
                                         patternPolicy_ == PatternPolicy::RebuildWhenChanged))
    return false;
  stats.reservedBlockPairs = static_cast<std::int64_t>(assembler_.GetNumReservedPairs());
  if (!update.grew) {
    ++stats.patternFits;
    return true;
  }
  ++stats.contactPatternBuilds;
  stats.patternBuilds = assembler_.GetNumPatternBuilds();
  stats.patternGrowths = assembler_.GetNumPatternGrowths();
  stats.hessianNonzeros = assembler_.CountOwnedColumnEntries();
  linear_.SetHessianNonzeros(stats.hessianNonzeros);
  AddAnalysisTimes(stats);
  stats.analysisSeconds += SecondsSince(start);
  return true;
}

void NewtonSolver::AddAnalysisTimes(SceneStats& stats) const {
  AnalysisTimes const& times = assembler_.GetLastAnalysisTimes();
  stats.orderingSeconds += times.orderingSeconds;
  stats.patternSeconds += times.patternSeconds;
  stats.slotTableSeconds += times.slotTableSeconds;
}

bool NewtonSolver::Solve(int stageIndex, StageContext stage, NewtonParams const& newton, SceneStats& stats,
                         Error& error) {
  stage.executor = &executor_;
  if (!BeginStage(stage, newton, stats, error)) return false;
  real energy = convergence_.Energy();
  if (!std::isfinite(energy))
    return Fail(ErrorCode::NonFiniteState, stageIndex, 0, "the incremental potential is not finite at the stage start",
                error);
  real lastStepNorm = 0;
  int const truncatedBefore = stats.truncatedSolves;
  for (int iteration = 1; iteration <= newton.maxIterations; ++iteration) {
    ++stats.newtonIterations;
    // the step: H δ = −∇E (projected where the exact H is indefinite)
    LinearSolveResult result;
    bool projected = false;
    if (!ComputeStep(stageIndex, iteration, newton, stats, result, projected, error)) return false;
    bool truncated = linear_.TakeTruncated(result, stats);
    if (!result.Ok() && !truncated) return LinearSolverFailed(stageIndex, iteration, result, error);

    // judge it; a step from a looser solve that looks converged is resumed
    // at the full tolerance first (a truncated one never ends Newton)
    real const resolution = convergence_.Resolution();
    ConvergenceTest::Verdict verdict;
    auto const judge = [&] {
      verdict = convergence_.Judge(gradient_, delta_, resolution);
      lastStepNorm = verdict.stepNorm;
      return verdict.Converged();
    };
    bool keepGoing = false;
    if (!linear_.Refine(judge, newton, result, truncated, keepGoing, stats))
      return LinearSolverFailed(stageIndex, iteration, result, error);
    if (!std::isfinite(verdict.stepNorm))
      return Fail(ErrorCode::NonFiniteState, stageIndex, iteration, "the Newton step is not finite", error);
    // converged: the step, and every term at its stage target
    bool const atTargets = problem_.AtTargets();
    bool const stepConverged = !keepGoing && !truncated && verdict.Converged();
    bool const converged = stepConverged && atTargets;
    if (converged && !verdict.stepConverged) ++stats.roundOffConvergences;

    // move: towards the terms' targets, a converged step whole, any other
    // along the line search
    auto const start = Clock::now();
    problem_.SaveIterate();
    if (!atTargets) {
      MoveWithTargets();
      energy = convergence_.Energy();
    } else if (stepConverged) {
      lineSearch_.TakeWhole();
    } else {
      real const before = energy;
      if (!lineSearch_.Search(newton, projected, verdict.slope, energy, stats)) {
        stats.lineSearchSeconds += SecondsSince(start);
        return Fail(ErrorCode::NewtonFailed, stageIndex, iteration,
                    "line search found no decrease of the incremental potential after " +
                        std::to_string(newton.maxLineSearchSteps) + " halvings (step norm " +
                        Format(verdict.stepNorm) + ", gradient norm " + Format(stats.gradientNorm) + ")",
                    error);
      }
      convergence_.RecordChange(before, energy, resolution);
    }
    stats.lineSearchSeconds += SecondsSince(start);
    if (!problem_.IsStateFinite())
      return Fail(ErrorCode::NonFiniteState, stageIndex, iteration, "the configuration is not finite", error);
    if (converged) {
      problem_.EndStage();
      return true;
    }
    // an iterate near the edge of the region the stage's contributors
    // cover: found again around it (the pattern may grow)
    if (problem_.BoundsSteps() && problem_.RecenterStepBounds()) {
      ++stats.contactRecenterings;
      if (!SetStageContributors(stats, error) || !linear_.Prepare(problem_, stats, error)) return false;
      energy = convergence_.Energy();  // the same Eᵢ, its terms summed in their new order
    }
  }
  std::string truncation;
  if (!problem_.AtTargets())
    truncation = "; a kinematic collider did not reach its target pose (a body in its way cannot move aside)";
  if (int const stageTruncated = stats.truncatedSolves - truncatedBefore; stageTruncated > 0)
    truncation += "; " + std::to_string(stageTruncated) + " linear solves stopped at the PCG cap of " +
                 std::to_string(linear_.GetPcg().maxIterations) + " iterations (PcgParams::maxIterations)";
  return Fail(ErrorCode::NewtonFailed, stageIndex, newton.maxIterations,
              "Newton did not converge within " + std::to_string(newton.maxIterations) + " iterations (gradient norm " +
                  Format(stats.gradientNorm) + ", tolerance " + Format(newton.velocityTolerance) +
                  " on the velocity-scaled step, last step " + Format(lastStepNorm) + ")" + truncation,
              error);
}

void NewtonSolver::MoveWithTargets() {
  // the step and the terms' motion towards their targets together, as far
  // as every term stays valid: no decrease test (the potential itself moves
  // with the targets); the line search takes over once they are there
  Span<real const> const delta(delta_.data(), delta_.size());
  real alpha = problem_.BoundsSteps() ? problem_.LargestSafeStep(delta, 1) : 1;
  for (int halving = 0; halving < 60; ++halving, alpha *= 0.5) {
    problem_.ApplyIncrementFromSaved(delta, alpha);
    if (problem_.AdvanceTargets(alpha)) break;
    problem_.RestoreIterate();
  }
  problem_.AcceptStep({delta, alpha, false});
}

bool NewtonSolver::ComputeStep(int stageIndex, int iteration, NewtonParams const& newton, SceneStats& stats,
                               LinearSolveResult& result, bool& projected, Error& error) {
  // With exact element Hessians, a matrix that is not positive definite, or
  // a step that is not a descent direction, sends this iteration once more
  // through assembly with projected Hessians; the next iteration tries the
  // exact ones again (at a minimum the exact Hessian is positive
  // semi-definite, so near convergence Newton is quadratic again).
  bool project = newton.hessianProjection == HessianProjection::Always;
  bool separateCouplings = false;  ///< own blocks modified apart from their couplings (last resort)
  Span<real> const gradient(gradient_.data(), gradient_.size());
  for (bool first = true;; first = false) {
    auto const start = Clock::now();
    problem_.Assemble(assembler_, gradient, AssemblyOptions{project});
    // across ranks each rank's owned entries of ∇E are complete: every rank
    // then holds all of ∇E, and the tests below agree on every rank
    if (ranks_.IsDistributed()) ranks_.GatherGradient(assembler_, gradient);
    stats.assemblySeconds += SecondsSince(start);
    stats.gradientNorm = gradient_.lpNorm<Eigen::Infinity>();
    if (!std::isfinite(stats.gradientNorm))
      return Fail(ErrorCode::NonFiniteState, stageIndex, iteration, "the gradient is not finite", error);
    if (first) linear_.BeginIteration(iteration, gradient_.norm(), newton);
    result = linear_.Solve(project, separateCouplings, newton, stats);
    bool const notDescent = linear_.Usable(result) && !(gradient_.dot(delta_) < 0);
    bool const indefinite = result.status == LinearSolveStatus::NotPositiveDefinite || notDescent;
    // an own block coupled with other DoFs whose modified sum left the Schur
    // complement indefinite: once more, the block modified apart from its
    // couplings (positive definite with projected couplings)
    if (project && indefinite && ownBlocks_.IsCoupled() && !linear_.OwnBlocksFailed() && !separateCouplings) {
      separateCouplings = true;
      ++stats.separateCouplingRetries;
      continue;
    }
    if (project || !indefinite) break;
    project = true;
    ++stats.projectionFallbacks;
  }
  // A projected matrix is positive semi-definite in exact arithmetic but can
  // fail the factorization by round-off (the articulated chain of 500 links
  // at dt = 1/240: a modified-Cholesky block at a condition number near 1e13)
  if (project) result = linear_.ShiftDiagonal(std::move(result), stats);
  if (fault_.failLinearSolveAtIteration == iteration && result.Ok()) {
    result.status = LinearSolveStatus::BackendError;
    result.reason = "failure injected by a test";
  }
  // (a backend's results agree across ranks; a test's fault may not)
  if (ranks_.IsDistributed()) result = AgreeOnResult(ranks_.GetCommunicator(), std::move(result));
  projected = project;
  return true;
}

bool NewtonSolver::LinearSolverFailed(int stageIndex, int iteration, LinearSolveResult const& failed,
                                      Error& error) const {
  std::string detail = failed.reason;
  if (failed.status == LinearSolveStatus::NotPositiveDefinite && failed.failingColumn >= 0)
    detail = "matrix not positive definite at column " + std::to_string(failed.failingColumn);
  return Fail(ErrorCode::LinearSolverFailed, stageIndex, iteration,
              "linear solver " + linear_.GetBackend()->GetDescription() + " failed (" +
                  std::string(ToString(failed.status)) + "): " + detail,
              error);
}

}  // namespace superdex::internal

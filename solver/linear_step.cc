#include <superdex/solver/linear_step.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include <superdex/core/stopwatch.h>
#include <superdex/linsolve/cholmod_solver.h>
#include <superdex/solver/newton_params.h>
#include <superdex/solver/scene_stats.h>

namespace superdex::internal {

namespace {
/// Reused factorizations: a numeric factorization runs at about this many
/// times the flop rate of a CG iteration with the factor (two triangular
/// solves and a product, memory-bound): measured 8.6 on a 9,963-DoF beam and
/// 15 on a 61,557-DoF one (docs/linear_solvers.md, "Reused factorizations").
/// Reuse is tried when a factorization is worth at least kMinReuseIterations
/// CG iterations, and CG stops at kMaxReuseIterations whatever the
/// factorization is worth.
constexpr real kFactorToSolveRate = 10;
constexpr int kMinReuseIterations = 3;
constexpr int kMaxReuseIterations = 50;
/// Reused-factor solves that fail in a row before a stage stops trying
constexpr int kMaxReuseFailures = 2;
/// NewtonParams::reuseForcingTerms: the loosest relative residual a
/// reused-factor CG stops at (the first iteration of a stage). Looser steps
/// cost Newton iterations, each an assembly: with η = 0.1 one CG iteration
/// usually meets it (M⁻¹H ≈ I)
constexpr real kMaxReuseForcingTerm = 0.1;
/// ... and its absolute accuracy: the error of the step, scaled as a
/// velocity like the Newton tolerance, this fraction of that tolerance
constexpr real kReuseStepAccuracy = 0.1;

using Clock = std::chrono::steady_clock;
}  // namespace

bool LinearStep::SetLinearSolver(LinearSolverType type, PcgParams const& pcg, Error& error) {
  if (!ValidatePcgParams(pcg, error)) return false;
  if (type != LinearSolverType::Auto) {
    auto available = AvailableLinearSolvers();
    if (std::find(available.begin(), available.end(), type) == available.end()) {
      error.Set(ErrorCode::InvalidArgument,
                "linearSolver " + std::string(ToString(type)) + " is not compiled into this build");
      return false;
    }
  }
  if (ranks_.IsDistributed()) {
    std::string const ranks =
        " across the " + std::to_string(ranks_.GetSize()) + " ranks of SceneParams.communicator";
    if (type == LinearSolverType::Cholmod || type == LinearSolverType::Dense) {
      error.Set(ErrorCode::InvalidArgument, "linearSolver " + std::string(ToString(type)) +
                                                " runs in one process; use PetscPcg or PetscMumps" + ranks);
      return false;
    }
    if (type == LinearSolverType::PetscPcg && pcg.preconditioner == PcgPreconditioner::Icc) {
      error.Set(ErrorCode::InvalidArgument,
                "PcgParams.preconditioner Icc (one incomplete factor of the whole matrix) runs in "
                "one process; use BlockJacobi (IC per rank), Gamg or BoomerAmg" + ranks);
      return false;
    }
  }
  requested_ = type;
  pcg_ = pcg;
  // a PCG backend with other settings is rebuilt (lazily, at the next solve)
  if (solver_ && solver_->GetType() == LinearSolverType::PetscPcg) solver_.reset();
  return true;
}

void LinearStep::Reserve(int numDofs, OrderingMethod ordering, std::int64_t hessianNonzeros) {
  ordering_ = ordering;
  hessianNonzeros_ = hessianNonzeros;
  schurRhs_.setZero(ownBlocks_.IsCoupled() ? numDofs : 0);
  orderedLengthScales_.setOnes(numDofs);
  orderedRhs_.setZero(numDofs);
  orderedSolution_.setZero(numDofs);
  reuseCg_.Reserve(numDofs);
}

bool LinearStep::Prepare(StageProblem const& problem, SceneStats& stats, Error& error) {
  SparseSymmetricMatrix const& matrix = assembler_.GetMatrix();
  // across ranks Auto is the distributed direct solver, as CHOLMOD is in one
  Error resolveError;
  LinearSolverType const type = ranks_.IsDistributed() && requested_ == LinearSolverType::Auto
                                    ? LinearSolverType::PetscMumps
                                    : ResolveLinearSolverType(requested_, matrix.size, resolveError);
  if (resolveError) {
    error = resolveError;
    return false;
  }
  if (!solver_ || solver_->GetType() != type) {
    if (type == LinearSolverType::Cholmod && ordering_ == OrderingMethod::SolverDefault)
      solver_ = std::make_unique<CholmodSolver>(CholmodOrdering::CholmodDefault);
    else if (type == LinearSolverType::Cholmod && ordering_ == OrderingMethod::Metis)
      solver_ = std::make_unique<CholmodSolver>(CholmodOrdering::GivenOrAmd);
    else
      solver_ = CreateLinearSolver(type, pcg_, error);
    if (!solver_) return false;
    solver_->SetParallelExecutor(executor_);
  }
  if (!solver_->IsAnalyzed() || solver_->GetAnalyzedPatternVersion() != matrix.patternVersion) {
    auto const start = Clock::now();
    if (!solver_->SetDistribution(ranks_.GetCommunicator(), assembler_.GetOwnedRowBegin(),
                                  assembler_.GetOwnedRowEnd())) {
      error.Set(ErrorCode::InvalidArgument,
                "linear solver " + solver_->GetDescription() + " does not run across MPI ranks");
      return false;
    }
    std::int64_t const builds = solver_->GetNumObjectBuilds();
    LinearSolveResult result = solver_->Analyze(matrix);
    stats.linearSolverObjectBuilds += solver_->GetNumObjectBuilds() - builds;
    if (result.Ok() && solver_->WantsNearNullSpace()) {
      // rigid-body modes at the current configuration, in the solver's order
      nearNullSpace_.setZero(matrix.size, 6);
      MatrixX natural = MatrixX::Zero(matrix.size, 6);
      problem.WriteRigidBodyModes(natural);
      for (int k = 0; k < 6; ++k)
        assembler_.PermuteToOrdered(Span<real const>(natural.col(k).data(), matrix.size),
                                    Span<real>(nearNullSpace_.col(k).data(), matrix.size));
      solver_->SetNearNullSpace(nearNullSpace_);
    }
    stats.analysisSeconds += SecondsSince(start);
    stats.symbolicSeconds += SecondsSince(start);
    if (!result.Ok()) {
      error.Set(ErrorCode::LinearSolverFailed,
                solver_->GetDescription() + " symbolic analysis failed: " + result.reason);
      return false;
    }
    ++stats.symbolicAnalyses;
    stats.linearSolver = solver_->GetDescription();
  }
  stats.factorNonzeros = solver_->GetFactorNonzeros();
  stats.factorFlops = solver_->GetFactorFlops();
  return true;
}

void LinearStep::BeginStage(Span<real const> lengthScales, NewtonParams const& newton, real h) {
  assembler_.PermuteToOrdered(lengthScales, Span<real>(orderedLengthScales_.data(), orderedLengthScales_.size()));
  // a reused-factor CG also stops once its error, scaled like the Newton
  // step, is a tenth of the Newton tolerance: a step near convergence is
  // known well enough to decide convergence and to take
  reuseStepTolerance_.scales = Span<real const>(orderedLengthScales_.data(), orderedLengthScales_.size());
  reuseStepTolerance_.tolerance = kReuseStepAccuracy * newton.velocityTolerance * h;
  reuseFailuresInRow_ = 0;
}

void LinearStep::BeginIteration(int iteration, real gradientNorm, NewtonParams const& newton) {
  // the inexact-Newton forcing term, once per iteration (a projected retry
  // has the same gradient): of the PCG solve, or of the reused-factor CG of
  // a direct solver
  forcingTerm_ = pcg_.relativeTolerance;
  reuseTolerance_ = newton.factorReuseTolerance;
  if (IsInexact()) {
    forcingTerm_ = ForcingTerm(iteration, gradientNorm, pcg_.relativeTolerance, pcg_.adaptiveMaxTolerance);
    solver_->SetRelativeTolerance(forcingTerm_);
  } else if (newton.reuseForcingTerms && !solver_->IsIterative()) {
    reuseTolerance_ = ForcingTerm(iteration, gradientNorm, newton.factorReuseTolerance,
                                  std::max(newton.factorReuseTolerance, kMaxReuseForcingTerm));
  }
}

LinearSolveResult LinearStep::Solve(bool project, bool separateCouplings, NewtonParams const& newton,
                                    SceneStats& stats) {
  // own blocks first (their blocks in the matrix become the identity): a
  // block that is not positive definite fails the iteration like the matrix
  LinearSolveResult result = ownBlocks_.Factorize(assembler_, project, separateCouplings, stats);
  ownBlocksFailed_ = !result.Ok();
  reusedLoose_ = false;
  if (ownBlocksFailed_) return result;
  if (SolveWithReusedFactor(newton, reuseTolerance_, /*resume=*/false, stats)) {
    reusedLoose_ = reuseTolerance_ > newton.factorReuseTolerance;
    return LinearSolveResult{};
  }
  result = Factorize(stats);
  if (result.Ok()) result = SolveWithCurrentMatrix(stats);
  return result;
}

LinearSolveResult LinearStep::ShiftDiagonal(LinearSolveResult result, SceneStats& stats) {
  for (real shift = 1e-8; !ownBlocksFailed_ && shift <= 1e-2 && result.status == LinearSolveStatus::NotPositiveDefinite;
       shift *= 100) {
    assembler_.ShiftDiagonal(shift);
    result = Factorize(stats);
    if (result.Ok()) result = SolveWithCurrentMatrix(stats);
    ++stats.diagonalShifts;
  }
  return result;
}

LinearSolveResult LinearStep::Factorize(SceneStats& stats) {
  auto const start = Clock::now();
  LinearSolveResult result;
  if (ownBlocks_.IsIdentityMatrix()) {  // the own blocks' factorizations are the Newton matrix's
    ++stats.factorizations;
    return result;
  }
  SparseSymmetricMatrix const& matrix = assembler_.GetMatrix();
  // across ranks a non-finite entry is refused by every rank at once: a rank
  // alone refusing it (the solver's own check) would leave the others
  // waiting in the backend's collective calls
  if (ranks_.IsDistributed() &&
      !ranks_.OnAllRanks(std::all_of(matrix.values.begin(), matrix.values.end(),
                                     [](real v) { return std::isfinite(v); }))) {
    result.status = LinearSolveStatus::InvalidInput;
    result.reason = "the assembled Hessian holds a non-finite entry";
  } else {
    result = solver_->Factorize(matrix);  // collective in the backend
  }
  stats.factorizationSeconds += SecondsSince(start);
  ++stats.factorizations;
  return result;
}

LinearSolveResult LinearStep::SolveWithCurrentMatrix(SceneStats& stats, bool resume) {
  auto const start = Clock::now();
  Span<real const> const gradient(gradient_->data(), gradient_->size());
  Span<real> const delta(delta_->data(), delta_->size());
  if (ownBlocks_.IsIdentityMatrix()) {
    *delta_ = -*gradient_;
    ownBlocks_.Solve(gradient, delta);
    stats.solveSeconds += SecondsSince(start);
    ++stats.linearSolves;
    return LinearSolveResult{};
  }
  OrderRhs();
  Span<real const> const rhs(orderedRhs_.data(), orderedRhs_.size());
  Span<real> const solution(orderedSolution_.data(), orderedSolution_.size());
  LinearSolveResult result = resume ? solver_->Resume(rhs, solution) : solver_->Solve(rhs, solution);
  assembler_.PermuteToNatural(Span<real const>(orderedSolution_.data(), orderedSolution_.size()), delta);
  ownBlocks_.Solve(gradient, delta);
  stats.solveSeconds += SecondsSince(start);
  stats.linearIterations += result.iterations;
  ++stats.linearSolves;
  return result;
}

void LinearStep::OrderRhs() {
  if (ownBlocks_.IsCoupled()) {
    // an own block coupled with other DoFs: the matrix holds its Schur
    // complement there, and the right-hand side is the complement's
    ownBlocks_.EliminateFromRhs(Span<real const>(gradient_->data(), gradient_->size()),
                                Span<real>(schurRhs_.data(), schurRhs_.size()));
    assembler_.PermuteToOrdered(Span<real const>(schurRhs_.data(), schurRhs_.size()),
                                Span<real>(orderedRhs_.data(), orderedRhs_.size()));
    return;
  }
  assembler_.PermuteToOrdered(Span<real const>(gradient_->data(), gradient_->size()),
                              Span<real>(orderedRhs_.data(), orderedRhs_.size()));
  orderedRhs_ = -orderedRhs_;
}

int LinearStep::ReuseIterationCap() const {
  double const factorFlops = solver_->GetFactorFlops();
  double const factorNonzeros = solver_->GetFactorNonzeros();
  if (!(factorFlops > 0) || !(factorNonzeros > 0)) return 0;
  // a CG iteration: L and Lᵀ solves (2 nnz(L) multiply-adds each) and the
  // product with the stored upper triangle (2 per entry)
  double const iterationFlops = 4 * factorNonzeros + 4 * double(hessianNonzeros_);
  return static_cast<int>(
      std::min<double>(kMaxReuseIterations, factorFlops / (kFactorToSolveRate * iterationFlops)));
}

bool LinearStep::SolveWithReusedFactor(NewtonParams const& newton, real tolerance, bool resume,
                                       SceneStats& stats) {
  if (!newton.reuseFactorization || ownBlocks_.IsIdentityMatrix() || solver_->IsIterative() ||
      !solver_->IsFactorized() || reuseFailuresInRow_ >= kMaxReuseFailures)
    return false;
  int const cap = ReuseIterationCap();
  if (cap < kMinReuseIterations) return false;
  auto const start = Clock::now();
  int const n = static_cast<int>(gradient_->size());
  OrderRhs();
  // across ranks each rank multiplies its own rows and gathers the rest; the
  // factor's solves are the backend's own, across the ranks (MUMPS)
  reuseCg_.SetProduct(ranks_.IsDistributed() ? &ranks_.GetProduct(assembler_) : nullptr);
  ReusedFactorCg::Result const result =
      reuseCg_.Solve(assembler_.GetMatrix(), *solver_, Span<real const>(orderedRhs_.data(), n),
                     Span<real>(orderedSolution_.data(), n), tolerance, cap, resume,
                     newton.reuseForcingTerms ? &reuseStepTolerance_ : nullptr, newton.singlePrecisionReusedFactor);
  stats.solveSeconds += SecondsSince(start);
  stats.linearIterations += result.iterations;
  ++stats.linearSolves;
  if (result.status != ReusedFactorCg::Status::Converged) {
    ++reuseFailuresInRow_;
    return false;
  }
  reuseFailuresInRow_ = 0;
  ++stats.reusedFactorSolves;
  if (result.reducedPrecision) ++stats.singlePrecisionSolves;
  Span<real> const delta(delta_->data(), delta_->size());
  assembler_.PermuteToNatural(Span<real const>(orderedSolution_.data(), n), delta);
  ownBlocks_.Solve(Span<real const>(gradient_->data(), gradient_->size()), delta);
  return true;
}

bool LinearStep::Usable(LinearSolveResult const& result) const {
  return result.Ok() || (result.truncated && pcg_.truncatedSteps);
}

bool LinearStep::TakeTruncated(LinearSolveResult const& result, SceneStats& stats) const {
  bool const take = !result.Ok() && Usable(result) && gradient_->dot(*delta_) < 0;
  if (take) ++stats.truncatedSolves;
  return take;
}

real LinearStep::ForcingTerm(int iteration, real gradientNorm, real tightest, real loosest) {
  // Eisenstat & Walker (1996), choice 2 with γ = 0.9, α = 2: η = γ (‖g‖/‖g₋₁‖)²,
  // safeguarded by γ η₋₁² when that exceeds 0.1; the first iteration of a
  // stage starts at the loosest tolerance
  real eta = loosest;
  if (iteration > 1 && previousGradientNorm_ > 0) {
    real const ratio = gradientNorm / previousGradientNorm_;
    eta = 0.9 * ratio * ratio;
    real const safeguard = 0.9 * previousForcingTerm_ * previousForcingTerm_;
    if (safeguard > 0.1) eta = std::max(eta, safeguard);
  }
  eta = std::clamp(eta, tightest, loosest);
  previousGradientNorm_ = gradientNorm;
  previousForcingTerm_ = eta;
  return eta;
}

}  // namespace superdex::internal

#include <superdex/scene/stage_solver.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <superdex/actors/actor.h>
#include <superdex/core/validate.h>
#include <superdex/linsolve/cholmod_solver.h>
#include <superdex/linsolve/petsc_distributed_matrix.h>
#include <superdex/scene/collectives.h>

namespace superdex::internal {

namespace {
/// Round-off resolution of the incremental potential, in units of its
/// magnitude Σ|terms|: a decrease smaller than this is not resolvable.
constexpr real kRoundOffUlps = 64;
/// Doublings of a projected step on a concave ray (at most 2²⁰ times the step)
constexpr int kMaxExpansions = 20;
/// Chord iterations of a second-order correction
constexpr int kMaxCorrections = 4;
/// Reused factorizations: a numeric factorization runs at about this many
/// times the flop rate of a CG iteration with the factor (two triangular
/// solves and a product, memory-bound): measured 8.6 on a 9,963-DoF beam and
/// 15 on a 61,557-DoF one (docs/linear_solvers.md, "Reused factorizations"). Reuse is tried when a factorization is worth
/// at least kMinReuseIterations CG iterations, and CG stops at
/// kMaxReuseIterations whatever the factorization is worth.
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
/// Constraints per chunk of the parallel assembly (~1 µs each)
constexpr int kConstraintGrain = 32;
using Clock = std::chrono::steady_clock;
double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}
/// Armijo's sufficient decrease (c = 1e-4) for a step of α along a direction
/// of slope ∇E·δ, with a round-off allowance of 1e-12 |E| plus the
/// resolution of Eᵢ (kRoundOffUlps ulps of its scale): a full Newton step
/// near the minimum, whose decrease is below what Eᵢ resolves, is taken
/// rather than halved on round-off until it no longer moves the iterate
bool SufficientDecrease(real energy, real trialEnergy, real alpha, real slope, real resolution) {
  real const allowance = 1e-12 * std::max(std::abs(energy), std::abs(trialEnergy)) + resolution;
  return std::isfinite(trialEnergy) && trialEnergy <= energy + 1e-4 * alpha * slope + allowance;
}
std::string Where(int stageIndex, int iteration) {
  return "stage " + std::to_string(stageIndex) + ", Newton iteration " + std::to_string(iteration);
}
}  // namespace

bool StageSolver::Analyze(DynamicArray<Actor*> const& actors,
                          DynamicArray<Constraint*> const& constraints, OrderingMethod ordering,
                          SceneStats& stats, Error& error) {
  ChooseOwnBlockSolves(actors, constraints);
  // count, then fill: DoF blocks and contributor DoF lists in a fixed order
  int numDofs = 0;
  DynamicArray<int> blockSizes;
  DynamicArray<DynamicArray<int>> contributorDofs;
  DynamicArray<int> firstContributor;
  for (Actor* actor : actors) {
    numDofs += actor->GetNumDofs();
    actor->AppendDofBlockSizes(blockSizes);
    firstContributor.push_back(static_cast<int>(contributorDofs.size()));
    actor->AppendContributorDofs(contributorDofs);
  }
  int maxDimension = 1, maxDofs = 1;
  for (Constraint* constraint : constraints) {
    firstContributor.push_back(static_cast<int>(contributorDofs.size()));
    // a folded constraint's terms reach the matrix through its actor
    if (constraint->foldedInto_ != nullptr)
      contributorDofs.emplace_back();
    else
      contributorDofs.emplace_back(constraint->dofs_);
    maxDimension = std::max(maxDimension, constraint->GetDimension());
    maxDofs = std::max(maxDofs, constraint->GetNumDofs());
  }
  firstContributor.push_back(static_cast<int>(contributorDofs.size()));  // the end of the last
  if (!assembler_.Analyze(numDofs, blockSizes, contributorDofs, ordering, error, numRanks_, rank_))
    return false;
  ordering_ = ordering;
  firstContributor_ = std::move(firstContributor);
  ownBlockActors_.clear();
  ownBlockContributors_.clear();
  for (std::size_t a = 0; a < actors.size(); ++a)
    if (actors[a]->SolvesOwnBlock()) {
      ownBlockActors_.push_back(actors[a]);
      ownBlockContributors_.push_back(firstContributor_[a]);
    }
  ownBlockRhs_.setZero(ownBlockActors_.empty() ? 0 : numDofs);
  ownBlocksCoupled_ = false;
  for (Actor* actor : ownBlockActors_) ownBlocksCoupled_ = ownBlocksCoupled_ || actor->HasOwnBlockCoupling();
  // every DoF in an own block, none coupled: the scene's matrix is the
  // identity once the blocks are factorized (constraints within one joint
  // are read into its block), and the linear solver is not called
  identityMatrix_ = !IsDistributed() && !ownBlockActors_.empty() && ownBlockActors_.size() == actors.size() &&
                    !ownBlocksCoupled_;
  schurRhs_.setZero(ownBlocksCoupled_ ? numDofs : 0);
  constraintWorkspace_.Reserve(maxDimension, maxDofs);
  maxConstraintDimension_ = maxDimension;
  maxConstraintDofs_ = maxDofs;
  ReserveThreadWorkspaces();
  gradient_.setZero(numDofs);
  delta_.setZero(numDofs);
  dofLengthScales_.setOnes(numDofs);
  orderedLengthScales_.setOnes(numDofs);
  dofInverseMasses_.setZero(numDofs);
  orderedRhs_.setZero(numDofs);
  orderedSolution_.setZero(numDofs);
  newtonStep_.setZero(numDofs);
  correctedStep_.setZero(numDofs);
  reuseCg_.Reserve(numDofs);
  if (IsDistributed()) {
    orderedGradient_.setZero(numDofs);
    rankCounts_.assign(numRanks_, 0);
    rankDisplacements_.assign(numRanks_, 0);
    rankSums_.assign(2 * static_cast<std::size_t>(numRanks_), 0);
  }
  stats.patternBuilds = assembler_.GetNumPatternBuilds();
  stats.numDofs = numDofs;
  stats.ranks = numRanks_;
  stats.ownedDofs = assembler_.GetOwnedRowEnd() - assembler_.GetOwnedRowBegin();
  // the whole pattern's entries: each rank stores only its part of it
  hessianNonzeros_ = assembler_.CountOwnedColumnEntries();
  if (IsDistributed()) {
    real count[1] = {static_cast<real>(hessianNonzeros_)};  // exact below 2⁵³
    SumInRankOrder(communicator_, count, rankSums_);
    hessianNonzeros_ = static_cast<std::int64_t>(count[0]);
  }
  stats.hessianNonzeros = hessianNonzeros_;
  return true;
}

void StageSolver::ChooseOwnBlockSolves(DynamicArray<Actor*> const& actors,
                                       DynamicArray<Constraint*> const& constraints) const {
  // in one process, an actor that can solve its own block does, unless a
  // constraint on it reaches another actor or more than one of its groups
  // (joints): that coupling needs the block in the scene's matrix. A
  // constraint on an articulated link, alone or with a body that is not a
  // link, is taken into the actor's own block instead (folded:
  // Actor::FoldConstraint; with another body, coupled by the block's Schur
  // complement)
  for (Actor* actor : actors) {
    actor->SetSolvesOwnBlock(!IsDistributed() && actor->CanSolveOwnBlock());
    actor->ClearFoldedConstraints();
  }
  DynamicArray<Constraint*> foldable;
  for (Constraint* constraint : constraints) {
    constraint->foldedInto_ = nullptr;
    for (int i = 0; i < constraint->GetNumActors(); ++i) {
      Actor* actor = constraint->GetActor(i);
      if (actor == nullptr || !actor->SolvesOwnBlock()) continue;
      if (constraint->FoldableLinkSlot() == i) {
        foldable.push_back(constraint);
        continue;
      }
      int const begin = actor->GetDofOffset(), end = begin + actor->GetNumDofs();
      int group = -1;
      bool local = true;
      for (int dof : constraint->dofs_) {
        if (dof < begin || dof >= end) {
          local = false;
          break;
        }
        int const g = actor->GetDofGroup(dof - begin);
        if (group >= 0 && g != group) local = false;
        group = g;
      }
      if (!local) actor->SetSolvesOwnBlock(false);
    }
  }
  // folded where the actor still solves its own block (another constraint
  // may have coupled it since)
  for (Constraint* constraint : foldable) {
    Actor* actor = constraint->GetActor(constraint->FoldableLinkSlot());
    if (actor->SolvesOwnBlock() && actor->FoldConstraint(constraint)) constraint->foldedInto_ = actor;
  }
}

LinearSolveResult StageSolver::FactorizeOwnBlocks(bool project, bool separateCouplings, SceneStats& stats) {
  LinearSolveResult result;
  if (ownBlockActors_.empty()) return result;
  auto const start = Clock::now();
  for (std::size_t a = 0; a < ownBlockActors_.size(); ++a)
    if (!ownBlockActors_[a]->FactorizeOwnBlock(assembler_, ownBlockContributors_[a], project, separateCouplings,
                                               result.reason)) {
      result.status = LinearSolveStatus::NotPositiveDefinite;
      if (project && result.reason.empty()) result.reason = "an actor's own block is not positive definite";
      break;
    }
  stats.factorizationSeconds += SecondsSince(start);
  return result;
}

void StageSolver::SolveOwnBlocks() {
  if (ownBlockActors_.empty()) return;
  ownBlockRhs_ = -gradient_;
  for (Actor* actor : ownBlockActors_)
    actor->SolveOwnBlock(Span<real const>(ownBlockRhs_.data(), ownBlockRhs_.size()),
                         Span<real>(delta_.data(), delta_.size()));
}

void StageSolver::SetCommunicator(Communicator const& communicator) {
  communicator_ = communicator;
  numRanks_ = communicator.GetSize();
  rank_ = communicator.GetRank();
  solver_.reset();
}

void StageSolver::GatherGradient() {
  int const n = static_cast<int>(gradient_.size());
  assembler_.PermuteToOrdered(Span<real const>(gradient_.data(), n), Span<real>(orderedGradient_.data(), n));
  AllgatherRows(communicator_, assembler_.GetPartRowStart(), rankCounts_, rankDisplacements_,
                Span<real>(orderedGradient_.data(), n));
  assembler_.PermuteToNatural(Span<real const>(orderedGradient_.data(), n), Span<real>(gradient_.data(), n));
}

LinearSolveResult StageSolver::FactorizeMatrix(SceneStats& stats) {
  auto const start = Clock::now();
  LinearSolveResult result;
  if (identityMatrix_) {  // the own blocks' factorizations are the Newton matrix's
    ++stats.factorizations;
    return result;
  }
  SparseSymmetricMatrix const& matrix = assembler_.GetMatrix();
  // across ranks a non-finite entry is refused by every rank at once: a rank
  // alone refusing it (the solver's own check) would leave the others
  // waiting in the backend's collective calls
  if (IsDistributed() &&
      !OnAllRanks(communicator_, std::all_of(matrix.values.begin(), matrix.values.end(),
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

void StageSolver::SetNumThreads(int numThreads) {
  executor_.SetNumThreads(numThreads);
  assembler_.SetExecutor(&executor_);
  ReserveThreadWorkspaces();
}

void StageSolver::ReserveThreadWorkspaces() {
  threadWorkspaces_.resize(executor_.GetNumThreads());
  for (ConstraintWorkspace& ws : threadWorkspaces_) ws.Reserve(maxConstraintDimension_, maxConstraintDofs_);
}

bool StageSolver::SetLinearSolver(LinearSolverType type, PcgParams const& pcg, Error& error) {
  if (!ValidatePcgParams(pcg, error)) return false;
  if (type != LinearSolverType::Auto) {
    auto available = AvailableLinearSolvers();
    if (std::find(available.begin(), available.end(), type) == available.end()) {
      error.Set(ErrorCode::InvalidArgument,
                "linearSolver " + std::string(ToString(type)) + " is not compiled into this build");
      return false;
    }
  }
  if (IsDistributed()) {
    std::string const ranks = " across the " + std::to_string(numRanks_) + " ranks of SceneParams.communicator";
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
  requestedSolver_ = type;
  pcg_ = pcg;
  // a PCG backend with other settings is rebuilt (lazily, at the next solve)
  if (solver_ && solver_->GetType() == LinearSolverType::PetscPcg) solver_.reset();
  return true;
}

bool StageSolver::EnsureSolverReady(DynamicArray<Actor*> const& actors, SceneStats& stats,
                                    Error& error) {
  SparseSymmetricMatrix const& matrix = assembler_.GetMatrix();
  // across ranks Auto is the distributed direct solver, as CHOLMOD is in one
  LinearSolverType const type = IsDistributed() && requestedSolver_ == LinearSolverType::Auto
                                    ? LinearSolverType::PetscMumps
                                    : ResolveLinearSolverType(requestedSolver_, matrix.size);
  if (!solver_ || solver_->GetType() != type) {
    if (type == LinearSolverType::Cholmod && ordering_ == OrderingMethod::SolverDefault)
      solver_ = std::make_unique<CholmodSolver>(CholmodOrdering::CholmodDefault);
    else if (type == LinearSolverType::Cholmod && ordering_ == OrderingMethod::Metis)
      solver_ = std::make_unique<CholmodSolver>(CholmodOrdering::GivenOrAmd);
    else
      solver_ = CreateLinearSolver(type, pcg_, error);
    if (!solver_) return false;
    solver_->SetParallelExecutor(&executor_);
  }
  if (!solver_->IsAnalyzed() || solver_->GetAnalyzedPatternVersion() != matrix.patternVersion) {
    auto const start = Clock::now();
    if (!solver_->SetDistribution(communicator_, assembler_.GetOwnedRowBegin(), assembler_.GetOwnedRowEnd())) {
      error.Set(ErrorCode::InvalidArgument, "linear solver " + solver_->GetDescription() +
                                                " does not run across MPI ranks");
      return false;
    }
    std::int64_t const builds = solver_->GetNumObjectBuilds();
    LinearSolveResult result = solver_->Analyze(matrix);
    stats.linearSolverObjectBuilds += solver_->GetNumObjectBuilds() - builds;
    if (result.Ok() && solver_->WantsNearNullSpace()) {
      // rigid-body modes at the current configuration, in the solver's order
      nearNullSpace_.setZero(matrix.size, 6);
      MatrixX natural = MatrixX::Zero(matrix.size, 6);
      for (Actor* actor : actors) actor->WriteRigidBodyModes(natural);
      for (int k = 0; k < 6; ++k)
        assembler_.PermuteToOrdered(Span<real const>(natural.col(k).data(), matrix.size),
                                    Span<real>(nearNullSpace_.col(k).data(), matrix.size));
      solver_->SetNearNullSpace(nearNullSpace_);
    }
    stats.analysisSeconds += SecondsSince(start);
    if (!result.Ok()) {
      error.Set(ErrorCode::LinearSolverFailed, solver_->GetDescription() +
                                                    " symbolic analysis failed: " + result.reason);
      return false;
    }
    ++stats.symbolicAnalyses;
    stats.linearSolver = solver_->GetDescription();
  }
  stats.factorNonzeros = solver_->GetFactorNonzeros();
  stats.factorFlops = solver_->GetFactorFlops();
  return true;
}

LinearSolveResult StageSolver::SolveNewtonSystem(SceneStats& stats, bool resume) {
  auto const start = Clock::now();
  if (identityMatrix_) {
    delta_ = -gradient_;
    SolveOwnBlocks();
    stats.solveSeconds += SecondsSince(start);
    ++stats.linearSolves;
    return LinearSolveResult{};
  }
  OrderNewtonRhs();
  Span<real const> const rhs(orderedRhs_.data(), orderedRhs_.size());
  Span<real> const solution(orderedSolution_.data(), orderedSolution_.size());
  LinearSolveResult result = resume ? solver_->Resume(rhs, solution) : solver_->Solve(rhs, solution);
  assembler_.PermuteToNatural(Span<real const>(orderedSolution_.data(), orderedSolution_.size()),
                              Span<real>(delta_.data(), delta_.size()));
  SolveOwnBlocks();
  stats.solveSeconds += SecondsSince(start);
  stats.linearIterations += result.iterations;
  ++stats.linearSolves;
  return result;
}

void StageSolver::OrderNewtonRhs() {
  if (ownBlocksCoupled_) {
    // an own block coupled with other DoFs: the matrix holds its Schur
    // complement there, and the right-hand side is the complement's
    schurRhs_ = -gradient_;
    for (Actor* actor : ownBlockActors_) actor->EliminateOwnBlockFromRhs(Span<real>(schurRhs_.data(), schurRhs_.size()));
    assembler_.PermuteToOrdered(Span<real const>(schurRhs_.data(), schurRhs_.size()),
                                Span<real>(orderedRhs_.data(), orderedRhs_.size()));
    return;
  }
  assembler_.PermuteToOrdered(Span<real const>(gradient_.data(), gradient_.size()),
                              Span<real>(orderedRhs_.data(), orderedRhs_.size()));
  orderedRhs_ = -orderedRhs_;
}

int StageSolver::ReuseIterationCap() const {
  double const factorFlops = solver_->GetFactorFlops();
  double const factorNonzeros = solver_->GetFactorNonzeros();
  if (!(factorFlops > 0) || !(factorNonzeros > 0)) return 0;
  // a CG iteration: L and Lᵀ solves (2 nnz(L) multiply-adds each) and the
  // product with the stored upper triangle (2 per entry)
  double const iterationFlops = 4 * factorNonzeros + 4 * double(hessianNonzeros_);
  return static_cast<int>(std::min<double>(kMaxReuseIterations, factorFlops / (kFactorToSolveRate * iterationFlops)));
}

bool StageSolver::SolveWithReusedFactor(NewtonParams const& newton, real tolerance, bool resume,
                                        SceneStats& stats) {
  if (!newton.reuseFactorization || identityMatrix_ || solver_->IsIterative() || !solver_->IsFactorized() ||
      reuseFailuresInRow_ >= kMaxReuseFailures)
    return false;
  int const cap = ReuseIterationCap();
  if (cap < kMinReuseIterations) return false;
  auto const start = Clock::now();
  int const n = static_cast<int>(gradient_.size());
  OrderNewtonRhs();
  // across ranks each rank multiplies its own rows and gathers the rest; the
  // factor's solves are the backend's own, across the ranks (MUMPS)
  if (IsDistributed()) ownedRowsProduct_.Set(communicator_, &assembler_.GetPartRowStart());
  reuseCg_.SetProduct(IsDistributed() ? &ownedRowsProduct_ : nullptr);
  ReusedFactorCg::Result const result =
      reuseCg_.Solve(assembler_.GetMatrix(), *solver_, Span<real const>(orderedRhs_.data(), n),
                     Span<real>(orderedSolution_.data(), n), tolerance, cap, resume,
                     newton.reuseForcingTerms ? &reuseStepTolerance_ : nullptr,
                     newton.singlePrecisionReusedFactor);
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
  assembler_.PermuteToNatural(Span<real const>(orderedSolution_.data(), n), Span<real>(delta_.data(), n));
  SolveOwnBlocks();
  return true;
}

bool StageSolver::Usable(LinearSolveResult const& result) const {
  return result.Ok() || (result.truncated && pcg_.truncatedSteps);
}

bool StageSolver::TakeTruncated(LinearSolveResult const& result, SceneStats& stats) const {
  bool const take = !result.Ok() && Usable(result) && gradient_.dot(delta_) < 0;
  if (take) ++stats.truncatedSolves;
  return take;
}

real StageSolver::ForcingTerm(int iteration, real gradientNorm, real tightest, real loosest) {
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

real StageSolver::TotalEnergy(DynamicArray<Actor*> const& actors,
                              DynamicArray<Constraint*> const& constraints, real h) {
  // each contributor is counted by the one rank that owns it (all of them in
  // one process), and the ranks' sums are added in rank order: every rank
  // gets the same bits
  real energy = 0, scale = 0;
  int const numActors = static_cast<int>(actors.size());
  for (int a = 0; a < numActors; ++a) {
    real const term = actors[a]->Energy(assembler_.GetOwnedContributors(
        firstContributor_[a], firstContributor_[a + 1] - firstContributor_[a]));
    energy += term;
    scale += std::abs(term) + actors[a]->EnergyRoundOffScale();
  }
  for (std::size_t c = 0; c < constraints.size(); ++c) {
    if (!assembler_.Owns(firstContributor_[numActors + c])) continue;
    real const term = constraints[c]->Energy(h, constraintWorkspace_);
    energy += term;
    scale += std::abs(term);
  }
  if (IsDistributed()) {
    real sums[2] = {energy, scale};
    SumInRankOrder(communicator_, sums, rankSums_);
    energy = sums[0];
    scale = sums[1];
  }
  energyScale_ = scale;
  return energy;
}

bool StageSolver::SecondOrderCorrection(DynamicArray<Actor*> const& actors,
                                        DynamicArray<Constraint*> const& constraints, real h,
                                        real energy, real slope, SceneStats& stats,
                                        real& trialEnergy) {
  // the actors are at q + δ, δ in delta_. Each correction δc solves
  // H δc = −Jᵀ (f(g(q + d)) − f(g + J δ)) at the current d = δ + Σ δc with the
  // factorization of H: a chord iteration back to the linearized constraint
  // values g + J δ. On success delta_ = d and newtonStep_ = the last δc.
  newtonStep_ = delta_;
  correctedStep_ = delta_;
  Span<real const> const step(newtonStep_.data(), newtonStep_.size());
  Span<real> gradient(gradient_.data(), gradient_.size());
  real previousEnergy = trialEnergy;
  for (int c = 0; c < kMaxCorrections; ++c) {
    gradient_.setZero();
    for (Constraint* constraint : constraints)
      constraint->AddCorrectionForce(h, step, gradient, constraintWorkspace_);
    if (!SolveNewtonSystem(stats).Ok()) break;
    correctedStep_ += delta_;
    Span<real const> const corrected(correctedStep_.data(), correctedStep_.size());
    for (Actor* actor : actors) actor->ApplyIncrementFromSaved(corrected, 1);
    real const correctedEnergy = TotalEnergy(actors, constraints, h);
    if (SufficientDecrease(energy, correctedEnergy, 1, slope, Resolution())) {
      trialEnergy = correctedEnergy;
      ++stats.secondOrderCorrections;
      newtonStep_ = delta_;  // the last δc
      delta_ = correctedStep_;
      return true;
    }
    if (!(correctedEnergy < previousEnergy)) break;
    previousEnergy = correctedEnergy;
  }
  delta_ = newtonStep_;
  return false;
}

real StageSolver::Resolution() const {
  return kRoundOffUlps * std::numeric_limits<real>::epsilon() * energyScale_;
}

real StageSolver::ScaledStepNorm(real h) const {
  return (delta_.cwiseAbs().cwiseProduct(dofLengthScales_)).maxCoeff() / h;
}

bool StageSolver::Solve(int stageIndex, StageCoefficients const& stage,
                        DynamicArray<Actor*> const& actors,
                        DynamicArray<Constraint*> const& constraints, Real3 const& gravity,
                        NewtonParams const& newton, SceneStats& stats, Error& error) {
  real const h = stage.duration;
  if (!EnsureSolverReady(actors, stats, error)) return false;
  bool const inexact = solver_->IsIterative() && pcg_.adaptiveTolerance;

  // constraints first: g(qᵢ⁰, p̂ᵢ⁰) at the committed configuration, before an
  // actor moves its first Newton iterate to its prediction (deformables,
  // rods and articulated actors do)
  // (the near-rigid cap reads the inverse masses there too)
  Span<real> const inverseMasses(dofInverseMasses_.data(), dofInverseMasses_.size());
  if (newton.nearRigidBeta > 0)
    for (Actor* actor : actors) actor->WriteDofInverseMasses(inverseMasses);
  int nearRigid = 0;
  for (Constraint* constraint : constraints)
    nearRigid += constraint->BeginStage(h, newton.nearRigidBeta, inverseMasses, constraintWorkspace_);
  stats.nearRigidConstraints = std::max(stats.nearRigidConstraints, nearRigid);
  for (Actor* actor : actors) {
    actor->BeginStage(stage, gravity);
    actor->SetFoldedConstraintHessian(newton.constraintHessian);
  }
  Span<real> const lengthScales(dofLengthScales_.data(), dofLengthScales_.size());
  for (Actor* actor : actors) actor->WriteDofLengthScales(lengthScales);
  assembler_.PermuteToOrdered(Span<real const>(dofLengthScales_.data(), dofLengthScales_.size()),
                              Span<real>(orderedLengthScales_.data(), orderedLengthScales_.size()));
  // a reused-factor CG also stops once its error, scaled like the Newton
  // step, is a tenth of the Newton tolerance: a step near convergence is
  // known well enough to decide convergence and to take
  reuseStepTolerance_.scales =
      Span<real const>(orderedLengthScales_.data(), orderedLengthScales_.size());
  reuseStepTolerance_.tolerance = kReuseStepAccuracy * newton.velocityTolerance * h;

  real energy = TotalEnergy(actors, constraints, h);
  if (!std::isfinite(energy)) {
    error.Set(ErrorCode::NonFiniteState,
              Where(stageIndex, 0) + ": the incremental potential is not finite at the stage start");
    return false;
  }

  Span<real> gradient(gradient_.data(), gradient_.size());
  int const numConstraintsStart = static_cast<int>(actors.size());
  real lastStepNorm = 0;
  int const truncatedBefore = stats.truncatedSolves;
  bool lastChangeUnresolved = false;  ///< the last accepted step changed Eᵢ below its resolution
  reuseFailuresInRow_ = 0;
  for (int iteration = 1; iteration <= newton.maxIterations; ++iteration) {
    ++stats.newtonIterations;

    // assemble gradient and Hessian into the cached pattern and solve
    // H δ = −∇E in the fill-reducing order (iterative solvers: to the
    // inexact-Newton forcing term when adaptive). With exact element
    // Hessians, a matrix that is not positive definite, or a step that is
    // not a descent direction, sends this iteration once more through
    // assembly with projected Hessians; the next iteration tries the exact
    // ones again (at a minimum the exact Hessian is positive semi-definite,
    // so near convergence they are usable and Newton is quadratic again).
    LinearSolveResult result;
    real forcingTerm = pcg_.relativeTolerance;
    // reused-factor CG: its tolerance this iteration, and whether δ came
    // from it at a tolerance looser than factorReuseTolerance
    real reuseTolerance = newton.factorReuseTolerance;
    bool reusedLoose = false;
    bool project = newton.hessianProjection == HessianProjection::Always;
    bool forcingSet = false;
    bool ownBlocksFailed = false;  ///< an actor's own block, not the matrix: no diagonal shift helps
    bool separateCouplings = false;  ///< own blocks modified apart from their couplings (last resort)
    for (;;) {
      auto start = Clock::now();
      assembler_.BeginAssembly(gradient);
      // the actors concurrently as well (staged: each contributor writes
      // only its own slots; each actor's loops nest in the same threads):
      // scenes of many small actors, such as many rods, would otherwise run
      // a few chunks at a time
      auto addActors = [&](int begin, int end, int) {
        for (int a = begin; a < end; ++a)
          actors[a]->AddGradientAndHessian(assembler_, firstContributor_[a], project);
      };
      assembler_.ParallelFor(static_cast<int>(actors.size()), 1, addActors);
      assembler_.ParallelFor(static_cast<int>(constraints.size()), kConstraintGrain,
                             [&](int begin, int end, int thread) {
                               for (int c = begin; c < end; ++c) {
                                 int const contributor = firstContributor_[numConstraintsStart + c];
                                 if (!assembler_.Evaluates(contributor) || constraints[c]->foldedInto_) continue;
                                 constraints[c]->AddGradientAndHessian(
                                     h, assembler_, contributor, newton.constraintHessian, project,
                                     threadWorkspaces_[thread]);
                               }
                             });
      assembler_.FinishAssembly();
      // across ranks each rank's owned entries of ∇E are complete: every
      // rank then holds all of ∇E, and the tests below agree on every rank
      if (IsDistributed()) GatherGradient();
      stats.assemblySeconds += SecondsSince(start);
      stats.gradientNorm = gradient_.lpNorm<Eigen::Infinity>();
      if (!std::isfinite(stats.gradientNorm)) {
        error.Set(ErrorCode::NonFiniteState,
                  Where(stageIndex, iteration) + ": the gradient is not finite");
        return false;
      }

      // the inexact-Newton forcing term, once per iteration (a projected
      // retry has the same gradient): of the PCG solve, or of the
      // reused-factor CG of a direct solver
      if (!forcingSet) {
        forcingSet = true;
        if (inexact) {
          forcingTerm = ForcingTerm(iteration, gradient_.norm(), pcg_.relativeTolerance,
                                    pcg_.adaptiveMaxTolerance);
          solver_->SetRelativeTolerance(forcingTerm);
        } else if (newton.reuseForcingTerms && !solver_->IsIterative()) {
          reuseTolerance = ForcingTerm(iteration, gradient_.norm(), newton.factorReuseTolerance,
                                       std::max(newton.factorReuseTolerance, kMaxReuseForcingTerm));
        }
      }
      // actors that solve their own blocks first (their blocks in the
      // matrix become the identity): a block that is not positive definite
      // sends the iteration to the projected retry like the matrix would
      LinearSolveResult ownBlocks = FactorizeOwnBlocks(project, separateCouplings, stats);
      ownBlocksFailed = !ownBlocks.Ok();
      if (ownBlocksFailed) {
        result = std::move(ownBlocks);
        reusedLoose = false;
      } else if (SolveWithReusedFactor(newton, reuseTolerance, /*resume=*/false, stats)) {
        result = LinearSolveResult{};
        reusedLoose = reuseTolerance > newton.factorReuseTolerance;
      } else {
        reusedLoose = false;
        result = FactorizeMatrix(stats);
        if (result.Ok()) result = SolveNewtonSystem(stats);
      }
      bool const notDescent = Usable(result) && !(gradient_.dot(delta_) < 0);
      bool const indefinite = result.status == LinearSolveStatus::NotPositiveDefinite || notDescent;
      // an own block coupled with other DoFs whose modified sum left the
      // Schur complement indefinite: once more, the block modified apart
      // from its couplings (positive definite with projected couplings)
      if (project && indefinite && ownBlocksCoupled_ && !ownBlocksFailed && !separateCouplings) {
        separateCouplings = true;
        ++stats.separateCouplingRetries;
        continue;
      }
      if (project || !indefinite) break;
      project = true;
      ++stats.projectionFallbacks;
    }
    // A projected matrix is positive semi-definite in exact arithmetic but
    // can fail the factorization by round-off (the articulated chain of 500
    // links at dt = 1/240, step 679: its modified-Cholesky block is a sum of
    // rank-one updates at a condition number near 1e13). Shift its diagonal
    // by 1e-8 |Hⱼⱼ|, then 100× more, up to 1e-2, before failing: a Levenberg
    // step, still a descent direction; the minimizer is unchanged.
    for (real shift = 1e-8; project && !ownBlocksFailed && shift <= 1e-2 &&
                            result.status == LinearSolveStatus::NotPositiveDefinite;
         shift *= 100) {
      assembler_.ShiftDiagonal(shift);
      result = FactorizeMatrix(stats);
      if (result.Ok()) result = SolveNewtonSystem(stats);
      ++stats.diagonalShifts;
    }
    if (fault_.failLinearSolveAtIteration == iteration && result.Ok()) {
      result.status = LinearSolveStatus::BackendError;
      result.reason = "failure injected by a test";
    }
    // (a backend's results agree across ranks; a test's fault may not)
    if (IsDistributed()) result = AgreeOnResult(communicator_, std::move(result));
    auto const linearSolverFailed = [&](LinearSolveResult const& failed) {
      std::string detail = failed.reason;
      if (failed.status == LinearSolveStatus::NotPositiveDefinite && failed.failingColumn >= 0)
        detail = "matrix not positive definite at column " + std::to_string(failed.failingColumn);
      error.Set(ErrorCode::LinearSolverFailed, Where(stageIndex, iteration) + ": linear solver " +
                                                    solver_->GetDescription() + " failed (" +
                                                    std::string(ToString(failed.status)) + "): " + detail);
      return false;
    };
    // a CG solve stopped at its cap is an inexact Newton step (truncated
    // Newton) when it descends; the line search judges it
    bool truncated = TakeTruncated(result, stats);
    if (!result.Ok() && !truncated) return linearSolverFailed(result);

    // Converged when the step, scaled to the velocity of material points, is
    // below the tolerance (rotations count by the motion of the body's rms
    // radius, Actor::WriteDofLengthScales), or at a stall on the round-off
    // floor of Eᵢ: the energy decrease the full step predicts, −∇E·δ (the
    // Newton decrement), and the change the last accepted step made are both
    // below the resolution of Eᵢ (kRoundOffUlps ulps of Σ|terms| and the
    // actors' round-off scales), so no line search can tell the iterate from
    // the minimum. Such a step is taken whole. Larger steps get a
    // backtracking line search on Eᵢ (Armijo, c = 1e-4, with a round-off
    // allowance of 1e-12 |E| plus the resolution).
    // A step from a looser solve (the inexact-Newton forcing term, or
    // truncated at the PCG cap) that looks converged is first resumed from
    // where it stopped, at the full tolerance; still truncated when the
    // resumptions stop gaining, it is taken but does not end Newton.
    real const resolution = Resolution();
    real stepNorm = 0, slope = 0;
    bool stepConverged = false, stalled = false;
    auto const judge = [&] {
      stepNorm = lastStepNorm = ScaledStepNorm(h);
      slope = gradient_.dot(delta_);
      stepConverged = stepNorm <= newton.velocityTolerance;
      stalled = lastChangeUnresolved && -slope <= resolution;
    };
    judge();
    // resumed again while it stays truncated and each resumption at least
    // halves the residual (restarted CG still converges, more slowly)
    // A reused-factor step from a forcing term that looks converged is
    // continued to factorReuseTolerance the same way; when that CG cannot
    // finish, the loose step is taken but does not end Newton (the next
    // iteration solves again, refactorizing after kMaxReuseFailures).
    if (reusedLoose && (stepConverged || stalled)) {
      if (SolveWithReusedFactor(newton, newton.factorReuseTolerance, /*resume=*/true, stats)) {
        judge();
      } else {
        stepConverged = stalled = false;
      }
    }
    bool loose = truncated || (inexact && forcingTerm > pcg_.relativeTolerance);
    while (loose && (stepConverged || stalled)) {
      real const previousResidual = result.relativeResidual;
      if (inexact) solver_->SetRelativeTolerance(pcg_.relativeTolerance);
      result = SolveNewtonSystem(stats, /*resume=*/true);
      truncated = TakeTruncated(result, stats);
      if (!result.Ok() && !truncated) return linearSolverFailed(result);
      judge();
      loose = truncated && result.relativeResidual <= 0.5 * previousResidual;
    }
    if (!std::isfinite(stepNorm)) {
      error.Set(ErrorCode::NonFiniteState, Where(stageIndex, iteration) + ": the Newton step is not finite");
      return false;
    }

    bool const converged = !truncated && (stepConverged || stalled);
    if (converged && !stepConverged) ++stats.roundOffConvergences;
    auto const start = Clock::now();
    for (Actor* actor : actors) actor->SaveIterate();
    Span<real const> const delta(delta_.data(), delta_.size());
    if (converged) {
      for (Actor* actor : actors) actor->ApplyIncrementFromSaved(delta, 1);
    } else {
      real alpha = 1;
      bool accepted = false, corrected = false;
      real trialEnergy = energy;
      for (int k = 0; k <= newton.maxLineSearchSteps; ++k, alpha *= 0.5) {
        for (Actor* actor : actors) actor->ApplyIncrementFromSaved(delta, alpha);
        trialEnergy = TotalEnergy(actors, constraints, h);
        if (SufficientDecrease(energy, trialEnergy, alpha, slope, Resolution())) {
          accepted = true;
          break;
        }
        // a rejected full step first tries its second-order correction
        // (constraints' curvature, docs/architecture.md)
        if (k == 0 && !constraints.empty() &&
            SecondOrderCorrection(actors, constraints, h, energy, slope, stats, trialEnergy)) {
          accepted = corrected = true;
          break;
        }
      }
      if (!accepted) {
        for (Actor* actor : actors) actor->RestoreIterate();
        stats.lineSearchSeconds += SecondsSince(start);
        error.Set(ErrorCode::NewtonFailed,
                  Where(stageIndex, iteration) +
                      ": line search found no decrease of the incremental potential after " +
                      std::to_string(newton.maxLineSearchSteps) + " halvings (step norm " +
                      Format(stepNorm) + ", gradient norm " +
                      Format(stats.gradientNorm) + ")");
        return false;
      }
      // Expansion: a projected Hessian overestimates the curvature
      // (H_p − H ⪰ 0). Where the full step decreased Eᵢ by more than 3/4 of
      // the slope (1.5 × the decrease the model predicts, ½|∇E·δ|), the true
      // curvature along δ is below half the model's or negative: near a
      // saddle of a folding cloth the projected steps are then a small
      // fraction of the way down and Newton crawls away from it by a constant
      // factor per iteration. Such a step is doubled while each doubling
      // decreases Eᵢ further (docs/architecture.md, measurements).
      if (project && !corrected && alpha == 1 && std::isfinite(trialEnergy) &&
          trialEnergy < energy + 0.75 * slope) {
        for (int k = 0; k < kMaxExpansions; ++k) {
          for (Actor* actor : actors) actor->ApplyIncrementFromSaved(delta, 2 * alpha);
          real const expandedEnergy = TotalEnergy(actors, constraints, h);
          if (!(expandedEnergy < trialEnergy)) break;
          alpha *= 2;
          trialEnergy = expandedEnergy;
        }
        for (Actor* actor : actors) actor->ApplyIncrementFromSaved(delta, alpha);
        if (alpha > 1) ++stats.lineSearchExpansions;
      }
      // the constraints' force estimates follow the accepted step
      if (corrected) {
        Span<real const> const correction(newtonStep_.data(), newtonStep_.size());
        for (Constraint* constraint : constraints) constraint->PredictForce(h, correction, 1, true);
      } else {
        for (Constraint* constraint : constraints) constraint->PredictForce(h, delta, alpha);
      }
      lastChangeUnresolved = std::abs(trialEnergy - energy) <= resolution;
      energy = trialEnergy;
    }
    stats.lineSearchSeconds += SecondsSince(start);
    bool finite = true;
    for (Actor* actor : actors) finite = finite && actor->IsStateFinite();
    if (!finite) {
      error.Set(ErrorCode::NonFiniteState, Where(stageIndex, iteration) + ": the configuration is not finite");
      return false;
    }

    if (converged) {
      for (Actor* actor : actors) actor->EndStage();
      for (Constraint* constraint : constraints) constraint->EndStage(h, constraintWorkspace_);
      return true;
    }
  }
  std::string truncation;
  if (int const stageTruncated = stats.truncatedSolves - truncatedBefore; stageTruncated > 0)
    truncation = "; " + std::to_string(stageTruncated) + " linear solves stopped at the PCG cap of " +
                 std::to_string(pcg_.maxIterations) +
                 " iterations (PcgParams::maxIterations)";
  error.Set(ErrorCode::NewtonFailed,
            Where(stageIndex, newton.maxIterations) + ": Newton did not converge within " +
                std::to_string(newton.maxIterations) + " iterations (gradient norm " +
                Format(stats.gradientNorm) + ", tolerance " +
                Format(newton.velocityTolerance) + " on the velocity-scaled step, last step " +
                Format(lastStepNorm) + ")" + truncation);
  return false;
}

}  // namespace superdex::internal

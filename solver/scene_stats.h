// SceneStats: what the scene counts since its creation and measures in its
// last step (Scene::GetStats); the Newton solver fills most of it.
#pragma once

#include <cstdint>
#include <limits>
#include <string>

#include <superdex/core/types.h>

namespace superdex {

/// Counters since the scene was created, and figures of the last step.
struct SceneStats {
  std::int64_t steps = 0;             ///< successful steps
  std::int64_t patternBuilds = 0;     ///< Hessian pattern + ordering + slot tables built
  std::int64_t symbolicAnalyses = 0;  ///< linear-solver symbolic analyses
  /// External solver objects created (PETSc Mat + KSP: once per pattern the
  /// PCG backend analyzes); 0 for CHOLMOD and dense.
  std::int64_t linearSolverObjectBuilds = 0;
  /// Successful steps that needed sub-stepping (SubstepParams): their
  /// attempt at the full dt failed.
  std::int64_t substeppedSteps = 0;
  /// Pattern rebuilds that kept the fill-reducing order: contributors whose
  /// DoF lists change between stages (contact pairs) needed entries the
  /// pattern lacked (docs/architecture.md, "A pattern that may change").
  /// patternBuilds counts the builds that ordered (METIS) anew.
  std::int64_t patternGrowths = 0;
  /// Stages whose changing contributors fit the pattern as analysed (their
  /// slot tables only; no rebuild).
  std::int64_t patternFits = 0;
  /// Block pairs reserved in the pattern for the changing contributors (kept
  /// while used, with hysteresis), now.
  std::int64_t reservedBlockPairs = 0;

  // last step (the figures below add up every attempt of a sub-stepped
  // step, failed attempts included: they are what the step cost)
  /// Sub-steps of the last step's last attempt: 1 for a step taken whole,
  /// k for one taken as k sub-steps of dt/k (0 before the first step).
  int substeps = 0;
  int newtonIterations = 0;
  int linearIterations = 0;        ///< CG iterations: PCG, and direct solvers' reused-factor solves
  int projectionFallbacks = 0;     ///< Newton iterations re-assembled with projected Hessians
  /// Projected Newton iterations re-assembled once more with the articulated
  /// actors' blocks modified apart from their couplings with other bodies
  /// (the Schur complement of the modified sum was not positive definite)
  int separateCouplingRetries = 0;
  /// Refactorizations of a projected Hessian that failed by round-off, with
  /// its diagonal shifted (1e-8 |Hⱼⱼ|, then ×100 up to 1e-2)
  int diagonalShifts = 0;
  int roundOffConvergences = 0;    ///< stages that converged on a Newton decrement at the
                                   ///< round-off floor of Eᵢ, not on the step norm
  /// Newton iterations whose projected step the line search lengthened
  /// (doubled while Eᵢ kept falling along a concave ray: near a saddle)
  int lineSearchExpansions = 0;
  /// Line searches that took the step limited per DoF share (a contact's
  /// vertices stopped at their own times of impact, the rest moving on)
  /// over the one along δ cut short (docs/contact.md, "A line search that
  /// never lets surfaces pass").
  int limitedSteps = 0;
  /// Newton iterations whose full step the line search took with a
  /// second-order correction for the constraints' curvature
  int secondOrderCorrections = 0;
  /// PCG solves stopped at PcgParams::maxIterations that Newton took as
  /// inexact steps (PcgParams::truncatedSteps)
  int truncatedSolves = 0;
  /// Numeric factorizations (direct solvers) or preconditioner set-ups
  /// (PCG), every retry included
  int factorizations = 0;
  /// Newton systems solved by CG with a reused factorization as the
  /// preconditioner (NewtonParams::reuseFactorization), without factorizing
  int reusedFactorSolves = 0;
  /// Of those, the ones that applied the factor from its single-precision
  /// copy (NewtonParams::singlePrecisionReusedFactor)
  int singlePrecisionSolves = 0;
  int linearSolves = 0;            ///< linear solves (one per Newton iteration, plus
                                   ///< inexact-Newton re-solves and second-order corrections)
  /// Constraints whose k and d the near-rigid cap (NewtonParams::
  /// nearRigidBeta) lowered: the most in any stage of the last step.
  int nearRigidConstraints = 0;
  real gradientNorm = 0;           ///< ‖∇E‖∞ at the last Newton iteration
  int numDofs = 0;
  int ranks = 1;      ///< MPI ranks of SceneParams::communicator
  int ownedDofs = 0;  ///< DoFs (Hessian rows) this rank owns: numDofs on one rank
  std::int64_t hessianNonzeros = 0;  ///< upper-triangle entries of the whole Hessian (on several ranks each stores its part)
  double factorNonzeros = 0;         ///< nnz(L) as the solver reports it
  double factorFlops = 0;
  std::string linearSolver;          ///< what ran, as the backend reports it
  /// Contributors whose DoF lists change between stages, in the last stage.
  int stageContributors = 0;
  /// Contact (docs/contact.md), at the end of the last step: candidate pairs
  /// of its last stage, those closer than the activation distance d̂, and
  /// their smallest gap [m] (+inf without candidates).
  int contactCandidates = 0;
  int activeContacts = 0;
  real minContactDistance = std::numeric_limits<real>::infinity();
  /// Pattern rebuilds (orderings and growths in the kept order) that the
  /// stages' changing contributors (contact pairs) caused, since creation.
  std::int64_t contactPatternBuilds = 0;
  /// In the last step: the candidate pairs found again within a stage
  /// because an iterate came near the edge of the stage's displacement
  /// bound (docs/contact.md, "The candidates").
  int contactRecenterings = 0;
  /// The contact system's share of the last step [s] (docs/contact.md,
  /// "Costs"): the broad phase (the stage's bounds, bounding-volume trees
  /// and candidate pairs, found again by a recentering), the narrow phase
  /// (the candidates' distances, barrier and friction energy, at every
  /// line-search trial), continuous collision detection (the safe step, the
  /// limited step, the first iterate's check) and the contact assembly (the
  /// candidates' gradient and Hessian blocks). The narrow phase and CCD run
  /// mostly within lineSearchSeconds (also at a stage's start and after a
  /// recentering), the contact assembly within assemblySeconds.
  double contactBroadPhaseSeconds = 0;
  double contactNarrowPhaseSeconds = 0;
  double contactCcdSeconds = 0;
  double contactAssemblySeconds = 0;
  // time of each phase of the last step [s]
  double analysisSeconds = 0;        ///< pattern build + symbolic analysis
  // ... analysisSeconds split: the block graph and its ordering (METIS), the
  // CSC pattern, the slot tables (and staging maps), the linear solver's
  // symbolic analysis
  double orderingSeconds = 0;
  double patternSeconds = 0;
  double slotTableSeconds = 0;
  double symbolicSeconds = 0;
  double assemblySeconds = 0;
  double factorizationSeconds = 0;  ///< numeric factorization, or PCG's value update + PC set-up
  double solveSeconds = 0;
  double lineSearchSeconds = 0;
  double stepSeconds = 0;
};

}  // namespace superdex

// Scene parameters and statistics (design.md §10).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include <superdex/assembly/ordering.h>
#include <superdex/constraints/constraint.h>
#include <superdex/core/communicator.h>
#include <superdex/core/types.h>
#include <superdex/linsolve/linear_solver.h>
#include <superdex/scene/integrator.h>

namespace superdex {

/// How Newton treats element Hessians that are not positive semi-definite
/// (hyperelastic tetrahedra and membranes under compression).
enum class HessianProjection {
  /// Exact element Hessians while the assembled matrix is positive definite
  /// (the inertia term usually makes it so); a Newton iteration whose matrix
  /// the linear solver reports not positive definite (or whose step is not a
  /// descent direction) is re-assembled with projected Hessians, and the next
  /// iteration tries the exact ones again. Near a minimum the exact Hessian is
  /// positive semi-definite, so Newton ends quadratically.
  WhenIndefinite,
  /// Every element Hessian projected to PSD (negative eigenvalues clamped):
  /// always a descent direction, but only linear convergence where elements
  /// are compressed (the projection drops curvature the solution needs).
  Always,
};

std::string_view ToString(HessianProjection projection);

/// Newton's method on each stage's incremental potential.
struct NewtonParams {
  int maxIterations = 50;        ///< > 0
  /// Converged when the step, scaled to the velocity of material points, is
  /// small: maxⱼ ℓⱼ |δqⱼ| / Δtᵢ <= velocityTolerance [m/s], with ℓⱼ = 1 m
  /// for translations (and every DoF of deformables, rods and articulated
  /// actors) and a rigid body's rms radius √(tr I_b / 2m) for its rotations
  /// (the rms motion of its mass per radian). > 0. Also converged when the
  /// Newton decrement −∇E·δ is below the round-off resolution of the
  /// incremental potential (counted in SceneStats::roundOffConvergences).
  real velocityTolerance = 1e-6;
  int maxLineSearchSteps = 40;   ///< backtracking halvings before failure, > 0
  HessianProjection hessianProjection = HessianProjection::WhenIndefinite;
  /// The constraint blocks of the Newton Hessian, for every constraint whose
  /// own choice is ConstraintHessian::SceneDefault (not allowed here).
  ConstraintHessian constraintHessian = ConstraintHessian::GeometricStiffness;
  /// The near-rigid cap β (off when 0, the default; finite and >= 0). With
  /// β > 0, every constraint whose k + d/Δtᵢ exceeds 4π²/(β² Δtᵢ² w) — w its
  /// inverse effective mass, the largest diagonal entry of J diag(M)⁻¹ Jᵀ at
  /// the stage start — has k and d scaled down to that bound for the stage
  /// (d/k kept; a saturated constraint keeps its force cap k ḡ), so that no
  /// constraint oscillates with a period below β Δtᵢ: the Newton Hessian stays
  /// well-conditioned for PCG, and the answer changes (a softer constraint),
  /// which is why it is opt-in. β = 1 is Drake SAP's near-rigid threshold;
  /// smaller β caps less. SceneStats::nearRigidConstraints counts the capped
  /// constraints; docs/constraints.md "Near-rigid constraints (opt-in)".
  real nearRigidBeta = 0;
  /// Direct linear solvers (CHOLMOD, dense): a Newton iteration first solves
  /// its own Hessian's system by conjugate gradients preconditioned with the
  /// last numeric factorization (of an earlier iteration or step, same
  /// pattern), to the relative residual `factorReuseTolerance`, and
  /// refactorizes only when that CG meets negative curvature or needs more
  /// iterations than one factorization costs (the cap comes from the factor's
  /// flop counts, docs/linear_solvers.md "Reused factorizations"). The step
  /// is the current Hessian's Newton step to that residual, so Newton
  /// converges to the same state. Off: every iteration refactorizes.
  /// SceneStats::factorizations and reusedFactorSolves count both kinds.
  bool reuseFactorization = true;
  real factorReuseTolerance = 1e-6;  ///< in (0, 1)
  /// With reuseFactorization: each reused-factor CG stops at the inexact-
  /// Newton forcing term of its iteration (Eisenstat–Walker choice 2, in
  /// [factorReuseTolerance, 0.1]: loose while Newton is far from the
  /// minimum, tight near it) instead of factorReuseTolerance, or once its
  /// estimated error, scaled like the Newton step, is a tenth of
  /// velocityTolerance. A step that meets the Newton tolerance from a looser
  /// solve is continued to one of those before Newton may stop, so the
  /// converged state stays within the tolerance of full Newton's. Off: every
  /// reused-factor solve goes to factorReuseTolerance.
  bool reuseForcingTerms = true;
  /// With reuseFactorization: the reused-factor CG applies a supernodal
  /// CHOLMOD factor from a copy of L rounded to single precision (half the
  /// memory traffic of its triangular solves, which run at memory speed), the
  /// arithmetic and CG's residual staying in double. The preconditioner is
  /// then L̃L̃ᵀ with L̃ = L rounded, still symmetric positive definite, and
  /// each Newton step is still the current Hessian's to the same tolerance.
  /// Skipped per factorization when L's diagonal spread says the Hessian is
  /// too ill-conditioned for single precision to pay (or a value does not fit
  /// a float); simplicial and dense factors always solve in double
  /// (docs/linear_solvers.md "Reused factorizations"). Off: double always.
  bool singlePrecisionReusedFactor = true;
};

/// Automatic sub-stepping: a policy for steps that fail, off by default.
///
/// With maxSubsteps > 1, a step of dt whose stage fails (Newton, the linear
/// solver or a non-finite state) is retried from the exact pre-step state as
/// 2 sub-steps of dt/2, then 4 of dt/4, ..., up to maxSubsteps; the first
/// attempt whose every sub-step succeeds is kept. If the last attempt fails
/// too, the scene is restored exactly and Step returns that attempt's Error.
/// The sub-steps are exactly the steps Step(dt/k) would take k times
/// (integrator history restarted where the step size changes), with the
/// kinematic targets set before the step reached along a straight line from
/// the old targets; docs/architecture.md ("Sub-stepping") gives the rules.
/// Off by default so that a Newton that does not converge at the requested
/// dt is reported, not hidden; SceneStats::substeps and substeppedSteps say
/// when it was used.
struct SubstepParams {
  /// The most sub-steps one step may be split into: a power of two >= 1.
  /// 1 (the default) turns sub-stepping off.
  int maxSubsteps = 1;
};

struct SceneParams {
  Real3 gravity{0, -9.81, 0};  ///< [m/s²]; y is up
  IntegratorType integrator = IntegratorType::BackwardEuler;
  NewtonParams newton;
  SubstepParams substeps;  ///< retry of a failed step as sub-steps (off by default)
  LinearSolverType linearSolver = LinearSolverType::Auto;
  PcgParams pcg;  ///< used when linearSolver is PetscPcg
  OrderingMethod ordering = OrderingMethod::Metis;
  /// Threads of the assembly (elements, stencils and constraints evaluated
  /// concurrently): 0 (the default) uses every CPU this process may run on,
  /// n >= 1 exactly n. The assembled Hessian and gradient, hence every
  /// result, are bit-identical for any thread count (docs/architecture.md,
  /// "Parallel assembly"). >= 0.
  int numThreads = 0;
  /// The MPI ranks the scene runs on (docs/distributed.md). The default is
  /// one process. With R > 1 ranks, every rank runs the same program and
  /// builds the same scene (the description and state are replicated); the
  /// DoFs are partitioned among the ranks (METIS k-way), each rank assembles
  /// the rows it owns, the linear solver runs across the ranks (PetscPcg
  /// without Icc, or PetscMumps; Auto picks PetscMumps), and every rank
  /// commits the same step. Every call that changes the scene or steps it is
  /// then collective: all ranks make it, in the same order. A communicator of
  /// one rank behaves exactly as the default.
  Communicator communicator;
};

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
  // time of each phase of the last step [s]
  double analysisSeconds = 0;        ///< pattern build + symbolic analysis
  double assemblySeconds = 0;
  double factorizationSeconds = 0;  ///< numeric factorization, or PCG's value update + PC set-up
  double solveSeconds = 0;
  double lineSearchSeconds = 0;
  double stepSeconds = 0;
};

}  // namespace superdex

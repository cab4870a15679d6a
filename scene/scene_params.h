// Scene parameters and statistics (design.md §10).
#pragma once

#include <cstdint>
#include <string>

#include <superdex/assembly/ordering.h>
#include <superdex/core/types.h>
#include <superdex/linsolve/linear_solver.h>
#include <superdex/scene/integrator.h>

namespace superdex {

/// Newton's method on each stage's incremental potential.
struct NewtonParams {
  int maxIterations = 50;        ///< > 0
  /// Converged when the step, scaled to a velocity, is small:
  /// maxⱼ |δqⱼ| / Δtᵢ <= velocityTolerance [m/s for translations, rad/s for
  /// rotations]. > 0.
  real velocityTolerance = 1e-6;
  int maxLineSearchSteps = 40;   ///< backtracking halvings before failure, > 0
};

struct SceneParams {
  Real3 gravity{0, -9.81, 0};  ///< [m/s²]; y is up
  IntegratorType integrator = IntegratorType::BackwardEuler;
  NewtonParams newton;
  LinearSolverType linearSolver = LinearSolverType::Auto;
  PcgParams pcg;  ///< used when linearSolver is PetscPcg
  OrderingMethod ordering = OrderingMethod::Metis;
};

/// Counters since the scene was created, and figures of the last step.
struct SceneStats {
  std::int64_t steps = 0;             ///< successful steps
  std::int64_t patternBuilds = 0;     ///< Hessian pattern + ordering + slot tables built
  std::int64_t symbolicAnalyses = 0;  ///< linear-solver symbolic analyses
  /// External solver objects created (PETSc Mat + KSP: once per pattern the
  /// PCG backend analyzes); 0 for CHOLMOD and dense.
  std::int64_t linearSolverObjectBuilds = 0;

  // last step
  int newtonIterations = 0;
  int linearIterations = 0;        ///< iterative solvers; 0 for direct ones
  int linearSolves = 0;            ///< linear solves (one per Newton iteration, plus
                                   ///< inexact-Newton re-solves)
  real gradientNorm = 0;           ///< ‖∇E‖∞ at the last Newton iteration
  int numDofs = 0;
  std::int64_t hessianNonzeros = 0;  ///< stored (upper triangle) entries
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

// Scene parameters (docs/architecture.md). The Newton options and the
// statistics a step reports are the solver's (solver/newton_params.h,
// solver/scene_stats.h).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include <superdex/assembly/ordering.h>
#include <superdex/contact/contact_params.h>
#include <superdex/core/communicator.h>
#include <superdex/core/types.h>
#include <superdex/linsolve/linear_solver.h>
#include <superdex/solver/newton_params.h>
#include <superdex/solver/scene_stats.h>
#include <superdex/stage/integrator.h>

namespace superdex {

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
  /// The most sub-steps one step may be split into: a power of two in
  /// [1, kMaxSubsteps]. 1 (the default) turns sub-stepping off.
  int maxSubsteps = 1;
};

/// The largest SubstepParams::maxSubsteps: 4096 sub-steps (12 halvings) of
/// a step that fails every attempt cost up to 8191 stage solves; a step that
/// needs dt/4096 to converge is better taken as shorter steps.
inline constexpr int kMaxSubsteps = 4096;

/// The largest SceneParams::numThreads: each assembly thread is a worker of
/// the threading library with its own stack and per-thread scratch; 1000
/// workers exhausted a 4 GB address space and aborted the process. 256 is
/// far above the CPUs of one node, which is what the assembly can use.
inline constexpr int kMaxThreads = 256;

struct SceneParams {
  Real3 gravity{0, -9.81, 0};  ///< [m/s²]; y is up
  IntegratorType integrator = IntegratorType::BackwardEuler;
  NewtonParams newton;
  SubstepParams substeps;  ///< retry of a failed step as sub-steps (off by default)
  LinearSolverType linearSolver = LinearSolverType::Auto;
  PcgParams pcg;  ///< used when linearSolver is PetscPcg
  OrderingMethod ordering = OrderingMethod::Metis;
  /// How the pattern follows contributors whose DoF lists change between
  /// stages (contact pairs): reserved pairs and growth in the kept order, or
  /// a new analysis whenever they change.
  PatternPolicy patternPolicy = PatternPolicy::ReserveAndGrow;
  /// Threads of the assembly (elements, stencils and constraints evaluated
  /// concurrently): 0 (the default) uses every CPU this process may run on,
  /// n >= 1 exactly n. The assembled Hessian and gradient, hence every
  /// result, are bit-identical for any thread count (docs/architecture.md,
  /// "Parallel assembly"). In [0, kMaxThreads].
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
  /// Contact between colliders (Scene::CreateCollider; docs/contact.md).
  ContactParams contact;
};

}  // namespace superdex

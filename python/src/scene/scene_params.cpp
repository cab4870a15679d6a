// scene/scene_params.h: SceneParams (with NewtonParams and SubstepParams), HessianProjection
// and the SceneStats a scene reports.
#include "defines.h"
#include "support/params_class.h"

namespace superdex::python {

void DefineSceneParams(py::module_& m) {
  py::enum_<HessianProjection>(
      m, "HessianProjection",
      "How Newton treats element Hessians that are not positive semi-definite.")
      .value("WhenIndefinite", HessianProjection::WhenIndefinite,
             "exact Hessians; an iteration whose matrix is not positive definite is "
             "re-assembled with projected ones (default)")
      .value("Always", HessianProjection::Always, "every element Hessian projected to PSD");

  using N = NewtonParams;
  ParamsClass<N>(m, "NewtonParams", "Newton's method on each stage's incremental potential.")
      .Field("max_iterations", &N::maxIterations, "> 0, default 50")
      .Field("velocity_tolerance", &N::velocityTolerance,
             "converged when max_j l_j |δq_j| / Δt <= velocity_tolerance [m/s], l_j = 1 m for "
             "displacements and a rigid body's rms radius for its rotations (or when the Newton "
             "decrement is at the round-off floor of the energy), > 0, default 1e-6")
      .Field("max_line_search_steps", &N::maxLineSearchSteps,
             "backtracking halvings before failure, > 0")
      .Field("hessian_projection", &N::hessianProjection,
             "HessianProjection, default WhenIndefinite")
      .Field("constraint_hessian", &N::constraintHessian,
             "ConstraintHessian of every constraint that does not choose its own, default "
             "GeometricStiffness (SceneDefault is refused here)")
      .Field("near_rigid_beta", &N::nearRigidBeta,
             "the near-rigid cap β, finite and >= 0; 0 (default) turns it off. With β > 0 a "
             "constraint whose k + d/Δt exceeds 4π²/(β² Δt² w), w its inverse effective mass "
             "(largest diagonal entry of J diag(M)⁻¹ Jᵀ at the stage start), has k and d scaled "
             "down to that bound for the stage (d/k and the force cap k·ḡ kept). It changes the "
             "answer; docs/constraints.md 'Near-rigid constraints (opt-in)'")
      .Field("reuse_factorization", &N::reuseFactorization,
             "direct solvers (CHOLMOD, dense): a Newton iteration first solves its own Hessian by "
             "CG preconditioned with the last factorization, to factor_reuse_tolerance, and "
             "refactorizes only when that does not pay; the converged state is full Newton's. "
             "Default True")
      .Field("factor_reuse_tolerance", &N::factorReuseTolerance,
             "relative residual of those CG solves, in (0, 1), default 1e-6")
      .Field("reuse_forcing_terms", &N::reuseForcingTerms,
             "with reuse_factorization: each reused-factor CG stops at its iteration's "
             "inexact-Newton forcing term (Eisenstat-Walker, in [factor_reuse_tolerance, 0.1]); "
             "a step that looks converged is continued to factor_reuse_tolerance before Newton "
             "stops, so the converged state is the same. Default True")
      .Field("single_precision_reused_factor", &N::singlePrecisionReusedFactor,
             "with reuse_factorization: the reused-factor CG applies a supernodal CHOLMOD factor "
             "from a single-precision copy of L (half the memory traffic; CG's residual and the "
             "Newton tolerance stay in double), unless the factor's diagonal spread says the "
             "Hessian is too ill-conditioned. Default True");

  ParamsClass<SubstepParams>(
      m, "SubstepParams",
      "Automatic sub-stepping, a policy for failed steps (off by default): with max_substeps "
      "> 1, a step of dt that fails is retried from the exact pre-step state as 2 sub-steps of "
      "dt/2, then 4 of dt/4, ..., up to max_substeps; if the last attempt fails, the scene is "
      "restored and the step raises that attempt's mochi.Error. The sub-steps equal steps of "
      "dt/k taken by hand (BDF2 history restarted where the step size changes; kinematic targets "
      "interpolated from the old target to the new one). docs/architecture.md, 'Sub-stepping'.")
      .Field("max_substeps", &SubstepParams::maxSubsteps,
             "the most sub-steps a step may be split into: a power of two >= 1; 1 (default) "
             "turns sub-stepping off");

  using S = SceneParams;
  ParamsClass<S>(m, "SceneParams",
                 "Scene parameters, validated by Scene.create. Nested structs (newton, substeps, pcg) "
                 "read by reference: params.newton.max_iterations = 20 changes params.")
      .Field("gravity", &S::gravity, "[m/s²], default (0, -9.81, 0): y is up")
      .Field("integrator", &S::integrator, "IntegratorType, default BackwardEuler")
      .Field("newton", &S::newton, "NewtonParams")
      .Field("substeps", &S::substeps,
             "SubstepParams: retry of a failed step as sub-steps (off by default)")
      .Field("linear_solver", &S::linearSolver, "LinearSolverType, default Auto")
      .Field("pcg", &S::pcg, "PcgParams, used when linear_solver is PetscPcg")
      .Field("ordering", &S::ordering, "OrderingMethod, default Metis")
      .Field("pattern_policy", &S::patternPolicy,
             "PatternPolicy: how the pattern follows contributors whose DoF lists change between "
             "stages, default ReserveAndGrow")
      .Field("num_threads", &S::numThreads,
             "threads of the assembly, >= 0; 0 (default): every CPU this process may use. Results "
             "are bit-identical for any count")
      .Field("contact", &S::contact, "ContactParams: contact between colliders (docs/contact.md)")
      .Field("communicator", &S::communicator,
             "Communicator: the MPI ranks the scene runs on; default Communicator(), one process. "
             "With Communicator.world() under mpirun every rank builds the same scene; "
             "linear_solver Auto is then MUMPS, and CHOLMOD, Dense and PCG with Icc are refused");

  using T = SceneStats;
  py::class_<T>(
      m, "SceneStats",
      "Counters since the scene was created, and figures of the last step (Scene.get_stats(); a "
      "snapshot, not updated by later steps).")
      .def_readonly("steps", &T::steps, "successful steps")
      .def_readonly("pattern_builds", &T::patternBuilds,
                    "Hessian pattern + ordering + slot tables built")
      .def_readonly("symbolic_analyses", &T::symbolicAnalyses, "linear-solver symbolic analyses")
      .def_readonly("pattern_growths", &T::patternGrowths,
                    "pattern rebuilds that kept the fill-reducing order (changing contributors needed "
                    "entries the pattern lacked)")
      .def_readonly("pattern_fits", &T::patternFits,
                    "stages whose changing contributors fit the analysed pattern (no rebuild)")
      .def_readonly("reserved_block_pairs", &T::reservedBlockPairs,
                    "block pairs reserved in the pattern for changing contributors, now")
      .def_readonly("linear_solver_object_builds", &T::linearSolverObjectBuilds,
                    "PETSc Mat + KSP creations; 0 for CHOLMOD and dense")
      .def_readonly("substepped_steps", &T::substeppedSteps,
                    "successful steps that needed sub-stepping (SubstepParams)")
      .def_readonly("substeps", &T::substeps,
                    "last step: sub-steps of its last attempt (1: taken whole; 0 before the "
                    "first step); the figures below add up every attempt, failed ones included")
      .def_readonly("newton_iterations", &T::newtonIterations, "last step")
      .def_readonly("linear_iterations", &T::linearIterations,
                    "last step: CG iterations (PCG, and direct solvers' reused-factor solves)")
      .def_readonly("projection_fallbacks", &T::projectionFallbacks,
                    "last step: Newton iterations re-assembled with projected Hessians")
      .def_readonly("separate_coupling_retries", &T::separateCouplingRetries,
                    "last step: projected Newton iterations re-assembled with the articulated actors' "
                    "blocks modified apart from their couplings with other bodies")
      .def_readonly("round_off_convergences", &T::roundOffConvergences,
                    "last step: stages converged on a Newton decrement at the round-off floor of "
                    "the energy, not on the step norm")
      .def_readonly("line_search_expansions", &T::lineSearchExpansions,
                    "last step: Newton iterations whose projected step the line search doubled "
                    "while the energy kept falling along a concave ray (near a saddle)")
      .def_readonly("limited_steps", &T::limitedSteps,
                    "last step: line searches that took the step limited per DoF share (contact "
                    "vertices stopped at their own times of impact) over the step cut short")
      .def_readonly("diagonal_shifts", &T::diagonalShifts,
                    "last step: refactorizations of a projected Hessian that failed by round-off, "
                    "with its diagonal shifted")
      .def_readonly("second_order_corrections", &T::secondOrderCorrections,
                    "last step: Newton iterations whose full step the line search took with a "
                    "second-order correction for the constraints' curvature")
      .def_readonly("truncated_solves", &T::truncatedSolves,
                    "last step: PCG solves stopped at max_iterations that Newton took as inexact "
                    "steps (PcgParams.truncated_steps)")
      .def_readonly("factorizations", &T::factorizations,
                    "last step: numeric factorizations (direct solvers) or preconditioner set-ups "
                    "(PCG)")
      .def_readonly("reused_factor_solves", &T::reusedFactorSolves,
                    "last step: Newton systems solved by CG with a reused factorization "
                    "(NewtonParams.reuse_factorization), without factorizing")
      .def_readonly("single_precision_solves", &T::singlePrecisionSolves,
                    "last step: of the reused-factor solves, those that applied the factor from "
                    "its single-precision copy (NewtonParams.single_precision_reused_factor)")
      .def_readonly("linear_solves", &T::linearSolves, "last step")
      .def_readonly("near_rigid_constraints", &T::nearRigidConstraints,
                    "last step: constraints whose k and d the near-rigid cap lowered (the most in "
                    "any stage)")
      .def_readonly("gradient_norm", &T::gradientNorm, "||∇E||∞ at the last Newton iteration")
      .def_readonly("num_dofs", &T::numDofs)
      .def_readonly("ranks", &T::ranks, "MPI ranks of SceneParams.communicator")
      .def_readonly("owned_dofs", &T::ownedDofs,
                    "DoFs (Hessian rows) this rank owns: num_dofs on one rank")
      .def_readonly("hessian_nonzeros", &T::hessianNonzeros, "stored (upper triangle) entries")
      .def_readonly("factor_nonzeros", &T::factorNonzeros, "nnz(L) as the solver reports it")
      .def_readonly("factor_flops", &T::factorFlops)
      .def_readonly("linear_solver", &T::linearSolver, "what ran, as the backend reports it")
      .def_readonly("stage_contributors", &T::stageContributors,
                    "contributors whose DoF lists change between stages, in the last stage")
      .def_readonly("contact_candidates", &T::contactCandidates, "candidate contact pairs of the last stage")
      .def_readonly("active_contacts", &T::activeContacts, "contacts closer than the activation distance")
      .def_readonly("min_contact_distance", &T::minContactDistance, "smallest contact gap [m] (inf: none)")
      .def_readonly("contact_pattern_builds", &T::contactPatternBuilds,
                    "pattern rebuilds the contact pairs caused, since creation")
      .def_readonly("contact_recenterings", &T::contactRecenterings,
                    "candidate searches again within the last step's stages (an iterate near its bound)")
      .def_readonly("contact_broad_phase_seconds", &T::contactBroadPhaseSeconds,
                    "last step: the contact bounds, trees and candidate pairs [s]")
      .def_readonly("contact_narrow_phase_seconds", &T::contactNarrowPhaseSeconds,
                    "last step: the candidates' distances, barrier and friction energy [s]")
      .def_readonly("contact_ccd_seconds", &T::contactCcdSeconds,
                    "last step: continuous collision detection (safe and limited steps) [s]")
      .def_readonly("contact_assembly_seconds", &T::contactAssemblySeconds,
                    "last step: the candidates' gradient and Hessian blocks [s]")
      .def_readonly("analysis_seconds", &T::analysisSeconds,
                    "pattern build + symbolic analysis [s]")
      .def_readonly("ordering_seconds", &T::orderingSeconds,
                    "of analysis_seconds: the block graph and its ordering (METIS) [s]")
      .def_readonly("pattern_seconds", &T::patternSeconds, "of analysis_seconds: the CSC pattern [s]")
      .def_readonly("slot_table_seconds", &T::slotTableSeconds,
                    "of analysis_seconds: the slot tables and staging maps [s]")
      .def_readonly("symbolic_seconds", &T::symbolicSeconds,
                    "of analysis_seconds: the linear solver's symbolic analysis [s]")
      .def_readonly("assembly_seconds", &T::assemblySeconds, "[s]")
      .def_readonly("factorization_seconds", &T::factorizationSeconds, "[s]")
      .def_readonly("solve_seconds", &T::solveSeconds, "[s]")
      .def_readonly("line_search_seconds", &T::lineSearchSeconds, "[s]")
      .def_readonly("step_seconds", &T::stepSeconds, "[s]")
      .def("__repr__", [](T const& s) {
        return "SceneStats(steps=" + std::to_string(s.steps) +
               ", pattern_builds=" + std::to_string(s.patternBuilds) +
               ", symbolic_analyses=" + std::to_string(s.symbolicAnalyses) +
               ", substeps=" + std::to_string(s.substeps) +
               ", newton_iterations=" + std::to_string(s.newtonIterations) +
               ", linear_iterations=" + std::to_string(s.linearIterations) +
               ", num_dofs=" + std::to_string(s.numDofs) + ", linear_solver='" + s.linearSolver +
               "', step_seconds=" + std::string(py::repr(py::float_(s.stepSeconds))) + ")";
      });
}

}  // namespace superdex::python

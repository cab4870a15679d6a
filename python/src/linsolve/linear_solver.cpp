// linsolve/linear_solver.h: solver types and PCG settings (used by
// SceneParams and Scene.set_linear_solver), and the standalone solver state
// machine analyze -> factorize -> solve.
#include "defines.h"
#include "support/arrays.h"
#include "support/params_class.h"

namespace superdex::python {

void DefineLinearSolver(py::module_& m) {
  py::enum_<LinearSolverType>(m, "LinearSolverType", "The Newton linear-solver backend.")
      .value("Auto", LinearSolverType::Auto,
             "dense up to DENSE_SOLVER_MAX_SIZE unknowns, CHOLMOD above")
      .value("Cholmod", LinearSolverType::Cholmod, "SuiteSparse CHOLMOD supernodal Cholesky")
      .value("PetscPcg", LinearSolverType::PetscPcg,
             "PETSc preconditioned CG (KSPCG), see PcgParams")
      .value("Dense", LinearSolverType::Dense, "dense Cholesky (Eigen), for tiny systems")
      .value("PetscMumps", LinearSolverType::PetscMumps,
             "MUMPS multifrontal LDL^T through PETSc, the direct solver that also runs across MPI ranks");

  py::enum_<PcgPreconditioner>(m, "PcgPreconditioner",
                               "Preconditioners of the PETSc PCG backend (docs/linear_solvers.md).")
      .value("None_", PcgPreconditioner::None, "plain CG (PCNONE; C++ PcgPreconditioner::None)")
      .value("Jacobi", PcgPreconditioner::Jacobi, "diagonal scaling (PCJACOBI)")
      .value("PointBlockJacobi", PcgPreconditioner::PointBlockJacobi,
             "inverse of each DoF block's diagonal block (PCVPBJACOBI)")
      .value("BlockJacobi", PcgPreconditioner::BlockJacobi,
             "block Jacobi: block_jacobi_blocks blocks, each its own IC(icc_levels)")
      .value("Icc", PcgPreconditioner::Icc,
             "incomplete Cholesky IC(icc_levels), Jacobi-scaled, RCM order, bounded shifts")
      .value("Gamg", PcgPreconditioner::Gamg,
             "PETSc smoothed-aggregation AMG with the rigid-body near-null space")
      .value("BoomerAmg", PcgPreconditioner::BoomerAmg, "hypre BoomerAMG, if PETSc has hypre");

  using P = PcgParams;
  ParamsClass<P>(
      m, "PcgParams",
      "Settings of the PETSc PCG backend. CG stops when ||r|| <= max(rtol ||b||, atol) or after "
      "max_iterations (reported as not converged; Newton may take it as a truncated step).")
      .Field("preconditioner", &P::preconditioner, "PcgPreconditioner, default Gamg")
      .Field("relative_tolerance", &P::relativeTolerance, "rtol, in (0, 1), default 1e-8")
      .Field("absolute_tolerance", &P::absoluteTolerance, "atol >= 0, default 1e-50")
      .Field("max_iterations", &P::maxIterations, "> 0, default 10000")
      .Field("adaptive_tolerance", &P::adaptiveTolerance,
             "inexact Newton: Eisenstat-Walker rtol per iteration, re-solved at "
             "relative_tolerance before convergence is accepted")
      .Field("adaptive_max_tolerance", &P::adaptiveMaxTolerance,
             "in [relative_tolerance, 1), default 0.5")
      .Field("truncated_steps", &P::truncatedSteps,
             "truncated Newton: a solve stopped at max_iterations is taken as an inexact step "
             "when it descends (never one that ends Newton); off: the cap fails the step")
      .Field("preconditioner_lag", &P::preconditionerLag,
             "the preconditioner is rebuilt every preconditioner_lag-th factorization, >= 1")
      .Field("reuse_amg_interpolation", &P::reuseAmgInterpolation,
             "Gamg: keep the first set-up's prolongators")
      .Field("block_jacobi_blocks", &P::blockJacobiBlocks, "BlockJacobi: number of blocks, >= 1")
      .Field("icc_levels", &P::iccLevels, "Icc and BlockJacobi: ICC fill levels, >= 0")
      .Field(
          "options", &P::options,
          "extra PETSc options ('-ksp_... -pc_...'), applied last; an unused option is an error");

  m.def(
       "validate_pcg_params",
       [](PcgParams const& params) { Checked([&](Error& e) { ValidatePcgParams(params, e); }); },
       py::arg("params"),
       "Checks every field; raises mochi.Error (InvalidArgument naming the field, NotSupported "
       "when the preconditioner is not in this build).")
      .def("available_pcg_preconditioners", &AvailablePcgPreconditioners,
           "The preconditioners compiled into this build (BoomerAmg only with hypre).")
      .def("available_linear_solvers", &AvailableLinearSolvers,
           "The backends compiled into this build (Auto not included).")
      .def(
          "resolve_linear_solver_type",
          [](LinearSolverType requested, int size) {
            return Checked([&](Error& error) { return ResolveLinearSolverType(requested, size, error); });
          },
          py::arg("requested"), py::arg("size"),
          "The backend `requested` resolves to for a system of `size` unknowns (Auto: Dense up to "
          "DENSE_SOLVER_MAX_SIZE, Cholmod above); raises mochi.Error for a negative size or a value "
          "that is not a LinearSolverType.");
  m.attr("DENSE_SOLVER_MAX_SIZE") = kDenseSolverMaxSize;
  m.attr("DENSE_SOLVER_MAX_UNKNOWNS") = kDenseSolverMaxUnknowns;

  py::enum_<LinearSolveStatus>(m, "LinearSolveStatus", "Outcome of a linear-solver call.")
      .value("Ok", LinearSolveStatus::Ok)
      .value("NotPositiveDefinite", LinearSolveStatus::NotPositiveDefinite,
             "direct backends: failing_column holds the column; PCG: negative curvature")
      .value("NotConverged", LinearSolveStatus::NotConverged,
             "iterative backends: reason, iterations, relative_residual")
      .value("BackendError", LinearSolveStatus::BackendError,
             "the external library reported an error")
      .value("InvalidState", LinearSolveStatus::InvalidState,
             "call out of order, or pattern changed since analyze")
      .value("InvalidInput", LinearSolveStatus::InvalidInput,
             "malformed pattern, wrong b size, or a non-finite value");

  using R = LinearSolveResult;
  py::class_<R>(m, "LinearSolveResult", "One typed result per linear-solver call (never NaN).")
      .def_readonly("status", &R::status)
      .def_readonly("failing_column", &R::failingColumn,
                    "NotPositiveDefinite: column in the matrix's order")
      .def_readonly("iterations", &R::iterations, "iterative backends; 0 for direct ones")
      .def_readonly("relative_residual", &R::relativeResidual,
                    "||Ax - b||/||b|| when computed, else 0")
      .def_readonly("reason", &R::reason, "human-readable cause when status is not Ok")
      .def("ok", &R::Ok)
      .def("__bool__", &R::Ok)
      .def("__repr__", [](R const& r) {
        return "LinearSolveResult(status=" + std::string(ToString(r.status)) +
               ", iterations=" + std::to_string(r.iterations) +
               ", relative_residual=" + std::string(py::repr(py::float_(r.relativeResidual))) +
               (r.reason.empty() ? "" : ", reason='" + r.reason + "'") + ")";
      });

  py::class_<LinearSolver>(
      m, "LinearSolver",
      "A linear solver, a state machine keyed on the matrix's pattern version: analyze(A) once "
      "per pattern, factorize(A) per set of values, solve(b) any number of times. Out-of-order "
      "calls return status InvalidState. Made by create_linear_solver.")
      .def("analyze", &LinearSolver::Analyze, py::arg("a"), "Symbolic analysis of a's pattern.")
      .def("factorize", &LinearSolver::Factorize, py::arg("a"),
           "Numeric factorization of a's values.")
      .def(
          "solve",
          [](LinearSolver& solver, py::handle b) {
            DynamicArray<real> const rhs = LoadReals(b, "b");
            DynamicArray<real> x(rhs.size());
            LinearSolveResult result = solver.Solve(rhs, x);
            return py::make_tuple(result, ToArray(Span<real const>(x)));
          },
          py::arg("b"),
          "Solves A x = b with the last factorization; returns (LinearSolveResult, x).")
      .def("is_analyzed", &LinearSolver::IsAnalyzed)
      .def("get_analyzed_pattern_version", &LinearSolver::GetAnalyzedPatternVersion)
      .def("get_type", &LinearSolver::GetType)
      .def("is_iterative", &LinearSolver::IsIterative, "True for iterative backends.")
      .def("set_relative_tolerance", &LinearSolver::SetRelativeTolerance,
           py::arg("relative_tolerance"),
           "Iterative backends: rtol of the next solves; direct backends ignore it.")
      .def("wants_near_null_space", &LinearSolver::WantsNearNullSpace)
      .def("set_near_null_space", &LinearSolver::SetNearNullSpace, py::arg("modes"),
           "size x k near-null-space vectors (AMG), after analyze and before factorize.")
      .def("get_num_object_builds", &LinearSolver::GetNumObjectBuilds)
      .def("get_description", &LinearSolver::GetDescription,
           "What really ran, as the backend reports it.")
      .def("get_factor_nonzeros", &LinearSolver::GetFactorNonzeros, "nnz(L) after analyze, or -1.")
      .def("get_factor_flops", &LinearSolver::GetFactorFlops,
           "Flops of the last factorization, or -1.");

  m.def(
      "create_linear_solver",
      [](LinearSolverType type, std::optional<PcgParams> const& pcg) {
        return Checked(
            [&](Error& e) { return CreateLinearSolver(type, pcg.value_or(PcgParams{}), e); });
      },
      py::arg("type"), py::arg("pcg") = py::none(),
      "A new solver of a concrete type (not Auto); pcg configures PetscPcg. Raises mochi.Error "
      "(InvalidArgument for Auto or bad pcg, NotSupported when not compiled in, BackendError "
      "when PETSc cannot start).");
}

}  // namespace superdex::python

// The linear-solver interface used by the Newton stage solver: a small state
// machine keyed on the matrix's pattern version.
//
//   Analyze(A)    once per pattern (symbolic analysis, allocation)
//   Factorize(A)  once per Newton iteration (numeric factorization / set-up)
//   Solve(b, x)   any number of times after Factorize
//
// Out-of-order calls (Factorize before Analyze, Factorize with a matrix whose
// pattern version differs from the analyzed one, Solve before Factorize) are
// reported as InvalidState, never undefined behaviour. Every call returns
// one typed result; failure is never signalled with NaN.
//
// The matrix passed to Analyze is already fill-reducing ordered by the
// assembler (METIS); backends factor it in the given order.
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include <superdex/core/communicator.h>
#include <superdex/core/error.h>
#include <superdex/core/types.h>
#include <superdex/linsolve/sparse_symmetric_matrix.h>

namespace superdex {

namespace internal {
class ParallelExecutor;
}

enum class LinearSolverType {
  Auto,      ///< dense up to DenseSolverMaxSize unknowns, CHOLMOD above
  Cholmod,   ///< SuiteSparse CHOLMOD supernodal Cholesky
  PetscPcg,  ///< PETSc preconditioned conjugate gradients (KSPCG), see PcgParams
  Dense,     ///< dense Cholesky (Eigen), for tiny systems
  PetscMumps,  ///< MUMPS multifrontal LDLᵀ through PETSc (petsc_mumps_solver.h): the
               ///< direct solver that also runs across MPI ranks
};

std::string_view ToString(LinearSolverType type);

/// Preconditioners of the PETSc PCG backend (docs/linear_solvers.md compares them).
enum class PcgPreconditioner {
  None,              ///< plain CG (PCNONE)
  Jacobi,            ///< diagonal scaling (PCJACOBI)
  PointBlockJacobi,  ///< inverse of each DoF block's diagonal block: 3×3 per node,
                     ///< 6×6 per rigid body (PCVPBJACOBI on the ordered blocks)
  BlockJacobi,       ///< block Jacobi: `blockJacobiBlocks` contiguous blocks of the
                     ///< METIS-ordered matrix, each with its own IC(`iccLevels`) (below)
  Icc,               ///< incomplete Cholesky IC(`iccLevels`) of the whole matrix, Jacobi-scaled
                     ///< and RCM-ordered, with bounded diagonal shifts (SuperDex's own, in a
                     ///< PCSHELL: docs/linear_solvers.md)
  Gamg,              ///< PETSc's smoothed-aggregation AMG (PCGAMG) with the rigid-body
                     ///< near-null space (3 translations, 3 rotations) of the scene's DoFs
  BoomerAmg,         ///< hypre BoomerAMG (PCHYPRE), if the installed PETSc has hypre
};

std::string_view ToString(PcgPreconditioner preconditioner);

/// Settings of the PETSc PCG backend. CG stops when ‖r‖₂ <= max(rtol ‖b‖₂, atol)
/// (PETSc's default test with a zero initial guess) or after maxIterations
/// iterations, which is reported as not converged (truncated: Newton takes
/// such a solve as an inexact step when `truncatedSteps` is set).
struct PcgParams {
  PcgPreconditioner preconditioner = PcgPreconditioner::Gamg;
  real relativeTolerance = 1e-8;   ///< rtol, in (0, 1)
  real absoluteTolerance = 1e-50;  ///< atol, >= 0
  int maxIterations = 10000;       ///< > 0
  /// Inexact Newton: the stage solver sets each iteration's rtol by the
  /// Eisenstat–Walker rule (choice 2: η = 0.9 (‖∇E‖/‖∇E_prev‖)², safeguarded,
  /// within [relativeTolerance, adaptiveMaxTolerance]) and re-solves at
  /// relativeTolerance before it accepts convergence.
  bool adaptiveTolerance = false;
  real adaptiveMaxTolerance = 0.5;  ///< in [relativeTolerance, 1)
  /// Truncated Newton: a solve stopped at maxIterations is taken as an
  /// inexact Newton step when it is a descent direction (a CG iterate from
  /// zero on a positive definite matrix always is), the line search judging
  /// it; such a step never ends Newton: one that looks converged is resumed
  /// (LinearSolver::Resume) until it meets relativeTolerance. Off: the cap
  /// fails the solve, and the step (LinearSolverFailed).
  bool truncatedSteps = true;
  /// The preconditioner is rebuilt at every `preconditionerLag`-th Factorize
  /// and reused (with the new matrix values in CG) in between; 1 = always
  /// rebuilt. >= 1.
  int preconditionerLag = 1;
  /// Gamg: keep the prolongators of the first set-up and recompute only the
  /// Galerkin coarse operators at later set-ups (PCGAMGSetReuseInterpolation).
  bool reuseAmgInterpolation = false;
  int blockJacobiBlocks = 8;  ///< BlockJacobi: number of blocks, >= 1
  int iccLevels = 0;          ///< Icc and BlockJacobi: fill levels of ICC, >= 0
  /// Extra PETSc options for power users, e.g. "-ksp_norm_type unpreconditioned
  /// -pc_gamg_threshold 0.02". Applied after the settings above (so they win);
  /// each option is scoped to this solver. An option PETSc does not use, or
  /// whose value it cannot read, is an error where the params are given
  /// (ValidatePcgParams).
  std::string options;
};

/// Checks every field of `params`; returns false and names the field and
/// value in `error` (InvalidArgument) when one is out of range, and
/// NotSupported when the preconditioner is not in this build. Non-empty
/// `options` are tried in one set-up on a small system (this starts PETSc):
/// an option PETSc does not use, or whose value it cannot read, is refused
/// here rather than at the next step.
bool ValidatePcgParams(PcgParams const& params, Error& error);

/// The preconditioners compiled into this build (BoomerAmg only with hypre).
DynamicArray<PcgPreconditioner> AvailablePcgPreconditioners();

/// Largest system size for which Auto picks the dense backend. Taken from the
/// measurement in docs/linear_solvers.md (perf/dense_vs_sparse): on rigid-body
/// chains dense Factorize+Solve is not slower than CHOLMOD up to 96 unknowns
/// (16 bodies) and slower from 102 on.
inline constexpr int kDenseSolverMaxSize = 96;

/// Largest system the dense backend accepts when chosen explicitly
/// (LinearSolverType::Dense); Analyze refuses larger ones with InvalidInput.
/// Its factorization costs n³/3 flops and n² memory: at this size 4.2e10
/// flops (~2–4 s per Newton iteration here, docs/linear_solvers.md), at
/// 12,000 unknowns minutes per step where CHOLMOD takes milliseconds.
inline constexpr int kDenseSolverMaxUnknowns = 5000;

enum class LinearSolveStatus {
  Ok,
  NotPositiveDefinite,  ///< direct backends: `failingColumn` holds the column where it
                        ///< failed; PCG: negative curvature met (column -1)
  NotConverged,         ///< iterative backends: `reason`, `iterations`, `relativeResidual`
  BackendError,         ///< the external library reported an error: `reason`
  InvalidState,         ///< call out of order, or pattern changed since Analyze
  InvalidInput,         ///< malformed pattern, wrong b/x size, or a non-finite value: `reason`
};

std::string_view ToString(LinearSolveStatus status);

struct LinearSolveResult {
  LinearSolveStatus status = LinearSolveStatus::Ok;
  int failingColumn = -1;      ///< NotPositiveDefinite: column in the matrix's (given) order
  int iterations = 0;          ///< iterative backends; 0 for direct ones
  real relativeResidual = 0;   ///< ‖Ax − b‖/‖b‖ when the backend computes it, else 0
  /// NotConverged at the iteration cap (nothing else went wrong): x holds
  /// the last iterate, finite, which Newton may take as an inexact step
  bool truncated = false;
  /// ApplyPreconditioner: the factor was applied in reduced precision
  bool reducedPrecision = false;
  std::string reason;          ///< human-readable cause when status != Ok

  bool Ok() const { return status == LinearSolveStatus::Ok; }
};

class LinearSolver {
 public:
  virtual ~LinearSolver() = default;

  /// Symbolic analysis of A's pattern (A.values is not read). Required before
  /// the first Factorize and after every change of A.patternVersion; discards
  /// any previous analysis and factorization, also when it fails.
  /// Returns InvalidInput if the pattern breaks the layout of
  /// sparse_symmetric_matrix.h (naming the entry), BackendError if the
  /// backend fails.
  LinearSolveResult Analyze(SparseSymmetricMatrix const& a);
  /// Numeric factorization of A's current values. SuperDex allocates nothing
  /// here (CHOLMOD itself allocates a few temporaries per call).
  /// Returns InvalidState before a successful Analyze, or if A.patternVersion
  /// (or size or nonzero count) differs from the analyzed pattern;
  /// InvalidInput if A.values has the wrong length or a non-finite entry;
  /// NotPositiveDefinite with `failingColumn` (in A's order) if A is not
  /// positive definite. A failed Factorize leaves no usable factor.
  LinearSolveResult Factorize(SparseSymmetricMatrix const& a);
  /// Solves A x = b with the last successful factorization; any number of
  /// times per Factorize. Does not allocate (CHOLMOD: after the first Solve
  /// following an Analyze). Returns InvalidState without a successful
  /// Factorize since the last Analyze; InvalidInput if b or x does not have
  /// A.size entries, b and x overlap, or b is not finite; BackendError if
  /// the solution overflows.
  LinearSolveResult Solve(Span<real const> b, Span<real> x);
  /// Solve that starts from x instead of zero: iterative backends continue
  /// from a truncated (or looser-tolerance) solution, with the iteration cap
  /// and the tolerance counted afresh against b; direct backends solve anew.
  /// Same checks and results as Solve.
  LinearSolveResult Resume(Span<real const> b, Span<real> x);
  /// x = M⁻¹ b for M the preconditioner that the last factorization gives, for
  /// conjugate gradients preconditioned by an earlier factorization
  /// (ReusedFactorCg). With `reducedPrecision` a backend may apply its factor
  /// rounded to a lower precision, where that is faster and safe: M is then
  /// the factorized matrix up to that rounding, still symmetric positive
  /// definite (CHOLMOD supernodal: L in single precision,
  /// SinglePrecisionFactor; docs/linear_solvers.md "Reused factorizations").
  /// Otherwise, and for every backend without such a copy, this is Solve.
  /// Same checks and results as Solve.
  LinearSolveResult ApplyPreconditioner(Span<real const> b, Span<real> x, bool reducedPrecision);

  bool IsAnalyzed() const { return analyzed_; }
  /// True when Solve can run: a Factorize succeeded since the last Analyze.
  bool IsFactorized() const { return factorized_; }
  std::uint64_t GetAnalyzedPatternVersion() const { return analyzedVersion_; }

  virtual LinearSolverType GetType() const = 0;
  /// True for iterative backends, which accept SetRelativeTolerance.
  virtual bool IsIterative() const { return false; }
  /// Iterative backends: the relative tolerance of the next Solve calls (the
  /// inexact-Newton forcing term). Direct backends ignore it (they solve to
  /// round-off).
  virtual void SetRelativeTolerance(real /*relativeTolerance*/) {}
  /// True when the backend uses a near-null space (AMG); then the caller
  /// passes it with SetNearNullSpace after each Analyze and before Factorize.
  virtual bool WantsNearNullSpace() const { return false; }
  /// The near-null-space vectors as columns of a size × k matrix in the
  /// analyzed (ordered) DoF order. Copied; only used when WantsNearNullSpace.
  virtual void SetNearNullSpace(MatrixX const& /*modes*/) {}
  /// How many times the backend created its external objects (PETSc Mat and
  /// KSP) since construction: once per Analyze for PETSc, 0 for the others.
  virtual std::int64_t GetNumObjectBuilds() const { return 0; }
  /// Threads the backend may run its own loops on (CHOLMOD: the
  /// single-precision preconditioner solve, SinglePrecisionFactor); nullptr
  /// (the default) runs them on the calling thread. The executor must
  /// outlive the solver's use of it. Results do not depend on it.
  virtual void SetParallelExecutor(internal::ParallelExecutor const* /*executor*/) {}
  /// Across MPI ranks (docs/distributed.md): the solves run on the ranks of
  /// `communicator`, this rank owning rows [rowBegin, rowEnd) of the analyzed
  /// (ordered) matrix; the ranks' ranges are contiguous, in rank order, and
  /// cover the matrix. Every rank then passes the whole matrix pattern, in
  /// which only the entries with an owned row or column hold the true values
  /// (the others hold partial sums and are not read); Solve reads the owned
  /// entries of b and writes all of x on every rank (gathered). Every call is
  /// collective and returns the same status on every rank. Set before
  /// Analyze (it discards any analysis). Returns false, changing nothing,
  /// for backends that run in one process (CHOLMOD, dense); a communicator of
  /// one rank is accepted by every backend and changes nothing.
  bool SetDistribution(Communicator const& communicator, int rowBegin, int rowEnd) {
    if (!DoSetDistribution(communicator, rowBegin, rowEnd)) return false;
    analyzed_ = factorized_ = false;
    return true;
  }
  /// What really ran, as the backend reports it ("CHOLMOD supernodal", ...).
  virtual std::string GetDescription() const = 0;
  /// Nonzeros of the Cholesky factor L (after Analyze), or -1 if unknown.
  virtual double GetFactorNonzeros() const = 0;
  /// Floating-point operations of the last factorization (after Analyze), or -1.
  virtual double GetFactorFlops() const = 0;

 protected:
  virtual LinearSolveResult DoAnalyze(SparseSymmetricMatrix const& a) = 0;
  virtual LinearSolveResult DoFactorize(SparseSymmetricMatrix const& a) = 0;
  virtual LinearSolveResult DoSolve(Span<real const> b, Span<real> x) = 0;
  virtual LinearSolveResult DoResume(Span<real const> b, Span<real> x) { return DoSolve(b, x); }
  /// SetDistribution's backend part (rowBegin <= rowEnd, checked by nobody
  /// else: the stage solver computes them from its partition).
  virtual bool DoSetDistribution(Communicator const& communicator, int /*rowBegin*/, int /*rowEnd*/) {
    return communicator.GetSize() <= 1;
  }
  virtual LinearSolveResult DoApplyPreconditioner(Span<real const> b, Span<real> x,
                                                  bool /*reducedPrecision*/) {
    return DoSolve(b, x);
  }

 private:
  enum class SolveKind { Solve, Resume, Preconditioner, ReducedPrecisionPreconditioner };
  LinearSolveResult CheckedSolve(Span<real const> b, Span<real> x, SolveKind kind);

  bool analyzed_ = false;
  bool factorized_ = false;
  int size_ = 0;
  std::int64_t analyzedNonzeros_ = 0;
  std::uint64_t analyzedVersion_ = 0;
};

/// The backends compiled into this build (Auto not included).
DynamicArray<LinearSolverType> AvailableLinearSolvers();

/// The backend `requested` resolves to for a system of `size` unknowns:
/// itself, or for Auto Dense up to kDenseSolverMaxSize unknowns and CHOLMOD
/// above. InvalidArgument (and Auto) for a value that is not a
/// LinearSolverType or a negative size.
LinearSolverType ResolveLinearSolverType(LinearSolverType requested, int size, Error& error);

/// A new solver of a concrete type (not Auto); `pcg` configures the PETSc
/// backend (and is ignored by the others). Returns nullptr and sets `error`
/// (InvalidArgument for Auto, a value outside the enum or invalid `pcg`,
/// NotSupported when the type is not compiled in, BackendError when PETSc
/// cannot be initialized).
std::unique_ptr<LinearSolver> CreateLinearSolver(LinearSolverType type, PcgParams const& pcg,
                                                 Error& error);
inline std::unique_ptr<LinearSolver> CreateLinearSolver(LinearSolverType type, Error& error) {
  return CreateLinearSolver(type, PcgParams{}, error);
}

}  // namespace superdex

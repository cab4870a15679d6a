#include <superdex/linsolve/linear_solver.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>

#include <superdex/core/config.h>
#include <superdex/linsolve/cholmod_solver.h>
#include <superdex/linsolve/dense_solver.h>
#include <superdex/linsolve/petsc_mumps_solver.h>
#include <superdex/linsolve/petsc_pcg_solver.h>
#include <superdex/linsolve/petsc_runtime.h>

#if SUPERDEX_HAS_PETSC
#include <petscconf.h>  // PETSC_HAVE_MUMPS
#endif

namespace superdex {

namespace {

LinearSolveResult MakeFailure(LinearSolveStatus status, std::string reason) {
  LinearSolveResult result;
  result.status = status;
  result.reason = std::move(reason);
  return result;
}

std::string FormatReal(real value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.17g", value);
  return buffer;
}

// Checks the upper-triangle CSC invariants of sparse_symmetric_matrix.h:
// colStart has size + 1 non-decreasing entries from 0, every column's rows
// are increasing, within [0, j], and end with the diagonal. Returns an empty
// string when the pattern is valid, else what is wrong, naming the field.
std::string CheckPattern(SparseSymmetricMatrix const& a) {
  if (a.size < 0) return "A.size must be >= 0, got " + std::to_string(a.size);
  if (a.colStart.size() != static_cast<std::size_t>(a.size) + 1) {
    return "A.colStart must have A.size + 1 = " + std::to_string(a.size + 1) + " entries, got " +
           std::to_string(a.colStart.size());
  }
  if (a.colStart[0] != 0) return "A.colStart[0] must be 0, got " + std::to_string(a.colStart[0]);
  if (a.rowIndex.size() != static_cast<std::size_t>(a.colStart.back())) {
    return "A.rowIndex must have A.colStart[size] = " + std::to_string(a.colStart.back()) +
           " entries, got " + std::to_string(a.rowIndex.size());
  }
  for (int j = 0; j < a.size; ++j) {
    int const begin = a.colStart[j];
    int const end = a.colStart[j + 1];
    if (end < begin) {
      return "A.colStart must be non-decreasing, but colStart[" + std::to_string(j + 1) +
             "] = " + std::to_string(end) + " < colStart[" + std::to_string(j) +
             "] = " + std::to_string(begin);
    }
    // the diagonal must be present, as the last (largest) row of the column
    if (end == begin || a.rowIndex[end - 1] != j) {
      return "A column " + std::to_string(j) +
             " has no diagonal entry (its last row index must be " + std::to_string(j) + ")";
    }
    for (int k = begin; k < end; ++k) {
      int const row = a.rowIndex[k];
      if (row < 0 || row > j) {
        return "A.rowIndex[" + std::to_string(k) + "] = " + std::to_string(row) + " in column " +
               std::to_string(j) + " is outside the upper triangle [0, " + std::to_string(j) + "]";
      }
      if (k > begin && row <= a.rowIndex[k - 1]) {
        return "A.rowIndex of column " + std::to_string(j) + " must be strictly increasing, got " +
               std::to_string(a.rowIndex[k - 1]) + " then " + std::to_string(row);
      }
    }
  }
  // the DoF blocks (optional): positive sizes covering the unknowns
  std::int64_t covered = 0;
  for (std::size_t b = 0; b < a.blockSizes.size(); ++b) {
    if (a.blockSizes[b] < 1)
      return "A.blockSizes[" + std::to_string(b) + "] = " + std::to_string(a.blockSizes[b]) + " must be >= 1";
    covered += a.blockSizes[b];
  }
  if (!a.blockSizes.empty() && covered != a.size)
    return "A.blockSizes must add up to A.size = " + std::to_string(a.size) + " (or be empty), got " +
           std::to_string(covered);
  return {};
}

// Returns an empty string when every stored value of A is finite, else names
// the first non-finite entry A(i, j).
std::string CheckValuesFinite(SparseSymmetricMatrix const& a) {
  for (int j = 0; j < a.size; ++j) {
    for (int k = a.colStart[j]; k < a.colStart[j + 1]; ++k) {
      if (!std::isfinite(a.values[k])) {
        return "A(" + std::to_string(a.rowIndex[k]) + ", " + std::to_string(j) + ") = A.values[" +
               std::to_string(k) + "] is not finite: " + FormatReal(a.values[k]);
      }
    }
  }
  return {};
}

// Index of the first non-finite entry of v, or -1.
std::ptrdiff_t FirstNonFinite(Span<real const> v) {
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i])) return static_cast<std::ptrdiff_t>(i);
  }
  return -1;
}

bool IsLinearSolverType(LinearSolverType type) {
  switch (type) {
    case LinearSolverType::Auto:
    case LinearSolverType::Cholmod:
    case LinearSolverType::PetscPcg:
    case LinearSolverType::Dense:
    case LinearSolverType::PetscMumps: return true;
  }
  return false;
}

}  // namespace

std::string_view ToString(LinearSolverType type) {
  switch (type) {
    case LinearSolverType::Auto:
      return "Auto";
    case LinearSolverType::Cholmod:
      return "Cholmod";
    case LinearSolverType::PetscPcg:
      return "PetscPcg";
    case LinearSolverType::Dense:
      return "Dense";
    case LinearSolverType::PetscMumps:
      return "PetscMumps";
  }
  return "Unknown";
}

std::string_view ToString(LinearSolveStatus status) {
  switch (status) {
    case LinearSolveStatus::Ok:
      return "Ok";
    case LinearSolveStatus::NotPositiveDefinite:
      return "NotPositiveDefinite";
    case LinearSolveStatus::NotConverged:
      return "NotConverged";
    case LinearSolveStatus::BackendError:
      return "BackendError";
    case LinearSolveStatus::InvalidState:
      return "InvalidState";
    case LinearSolveStatus::InvalidInput:
      return "InvalidInput";
  }
  return "Unknown";
}

LinearSolveResult LinearSolver::Analyze(SparseSymmetricMatrix const& a) {
  // a failed or repeated analysis invalidates everything before it
  analyzed_ = false;
  factorized_ = false;

  std::string const patternError = CheckPattern(a);
  if (!patternError.empty()) {
    return MakeFailure(LinearSolveStatus::InvalidInput, "Analyze: " + patternError);
  }

  LinearSolveResult result = DoAnalyze(a);
  if (!result.Ok()) return result;

  analyzed_ = true;
  size_ = a.size;
  analyzedNonzeros_ = a.NumNonzeros();
  analyzedVersion_ = a.patternVersion;
  return result;
}

LinearSolveResult LinearSolver::Factorize(SparseSymmetricMatrix const& a) {
  if (!analyzed_) {
    factorized_ = false;
    return MakeFailure(LinearSolveStatus::InvalidState,
                       "Factorize called before a successful Analyze");
  }
  // a matrix of another pattern leaves the analysis intact but the factor
  // unusable: the caller must Analyze the new pattern first
  if (a.patternVersion != analyzedVersion_) {
    factorized_ = false;
    return MakeFailure(LinearSolveStatus::InvalidState,
                       "Factorize: A.patternVersion = " + std::to_string(a.patternVersion) +
                           " differs from the analyzed pattern version " +
                           std::to_string(analyzedVersion_) + "; call Analyze first");
  }
  // O(1) consistency checks that catch a pattern rebuilt without a new version
  if (a.size != size_ || a.NumNonzeros() != analyzedNonzeros_ ||
      a.colStart.size() != static_cast<std::size_t>(size_) + 1 ||
      a.rowIndex.size() != static_cast<std::size_t>(analyzedNonzeros_)) {
    factorized_ = false;
    return MakeFailure(LinearSolveStatus::InvalidState,
                       "Factorize: A has size " + std::to_string(a.size) + " and " +
                           std::to_string(a.NumNonzeros()) +
                           " nonzeros but the analyzed pattern (version " +
                           std::to_string(analyzedVersion_) + ") has size " +
                           std::to_string(size_) + " and " + std::to_string(analyzedNonzeros_) +
                           "; the pattern changed without a new patternVersion");
  }
  if (a.values.size() != static_cast<std::size_t>(analyzedNonzeros_)) {
    factorized_ = false;
    return MakeFailure(LinearSolveStatus::InvalidInput,
                       "Factorize: A.values must have " + std::to_string(analyzedNonzeros_) +
                           " entries, got " + std::to_string(a.values.size()));
  }
  // O(nnz(A)), small next to the factorization; a NaN must not reach the
  // backend, which could return a NaN factor and report success
  std::string const valueError = CheckValuesFinite(a);
  if (!valueError.empty()) {
    factorized_ = false;
    return MakeFailure(LinearSolveStatus::InvalidInput, "Factorize: " + valueError);
  }

  LinearSolveResult result = DoFactorize(a);
  factorized_ = result.Ok();
  return result;
}

LinearSolveResult LinearSolver::Solve(Span<real const> b, Span<real> x) {
  return CheckedSolve(b, x, SolveKind::Solve);
}

LinearSolveResult LinearSolver::Resume(Span<real const> b, Span<real> x) {
  return CheckedSolve(b, x, SolveKind::Resume);
}

LinearSolveResult LinearSolver::ApplyPreconditioner(Span<real const> b, Span<real> x,
                                                    bool reducedPrecision) {
  return CheckedSolve(b, x,
                      reducedPrecision ? SolveKind::ReducedPrecisionPreconditioner
                                       : SolveKind::Preconditioner);
}

LinearSolveResult LinearSolver::CheckedSolve(Span<real const> b, Span<real> x, SolveKind kind) {
  bool const resume = kind == SolveKind::Resume;
  if (!factorized_) {
    return MakeFailure(LinearSolveStatus::InvalidState,
                       analyzed_
                           ? "Solve called without a successful Factorize since the last Analyze"
                           : "Solve called before Analyze and Factorize");
  }
  auto const n = static_cast<std::size_t>(size_);
  if (b.size() != n) {
    return MakeFailure(LinearSolveStatus::InvalidInput,
                       "Solve: b must have " + std::to_string(n) +
                           " entries (the factorized size), got " + std::to_string(b.size()));
  }
  if (x.size() != n) {
    return MakeFailure(LinearSolveStatus::InvalidInput,
                       "Solve: x must have " + std::to_string(n) +
                           " entries (the factorized size), got " + std::to_string(x.size()));
  }
  // overlap test through std::less, which gives a total order on pointers
  if (n > 0) {
    std::less<real const*> const less;
    real const* bBegin = b.data();
    real const* xBegin = x.data();
    if (less(bBegin, xBegin + n) && less(xBegin, bBegin + n)) {
      return MakeFailure(LinearSolveStatus::InvalidInput, "Solve: b and x must not overlap");
    }
  }
  if (std::ptrdiff_t const i = FirstNonFinite(b); i >= 0) {
    return MakeFailure(LinearSolveStatus::InvalidInput,
                       "Solve: b[" + std::to_string(i) + "] is not finite: " + FormatReal(b[i]));
  }

  if (resume) {
    if (std::ptrdiff_t const i = FirstNonFinite(Span<real const>(x.data(), x.size())); i >= 0) {
      return MakeFailure(LinearSolveStatus::InvalidInput,
                         "Resume: x[" + std::to_string(i) + "] is not finite: " + FormatReal(x[i]));
    }
  }
  LinearSolveResult result;
  switch (kind) {
    case SolveKind::Solve:
      result = DoSolve(b, x);
      break;
    case SolveKind::Resume:
      result = DoResume(b, x);
      break;
    case SolveKind::Preconditioner:
    case SolveKind::ReducedPrecisionPreconditioner:
      result = DoApplyPreconditioner(b, x, kind == SolveKind::ReducedPrecisionPreconditioner);
      break;
  }
  if (!result.Ok() && !result.truncated) return result;
  // a finite, positive definite factor can still overflow on a nearly
  // singular matrix; report it rather than hand back inf or NaN
  if (std::ptrdiff_t const i = FirstNonFinite(Span<real const>(x.data(), x.size())); i >= 0) {
    return MakeFailure(LinearSolveStatus::BackendError,
                       "Solve: the solution overflowed, x[" + std::to_string(i) +
                           "] = " + FormatReal(x[i]) + " (A is numerically singular)");
  }
  return result;
}

DynamicArray<LinearSolverType> AvailableLinearSolvers() {
  DynamicArray<LinearSolverType> types;
#if SUPERDEX_HAS_CHOLMOD
  types.push_back(LinearSolverType::Cholmod);
#endif
#if SUPERDEX_HAS_PETSC
  types.push_back(LinearSolverType::PetscPcg);
#endif
#if SUPERDEX_HAS_PETSC && defined(PETSC_HAVE_MUMPS)
  types.push_back(LinearSolverType::PetscMumps);
#endif
  types.push_back(LinearSolverType::Dense);
  return types;
}

LinearSolverType ResolveLinearSolverType(LinearSolverType requested, int size, Error& error) {
  if (!IsLinearSolverType(requested)) {
    error.Set(ErrorCode::InvalidArgument, "ResolveLinearSolverType: requested is not a LinearSolverType (" +
                                              std::to_string(static_cast<int>(requested)) + ")");
    return LinearSolverType::Auto;
  }
  if (size < 0) {
    error.Set(ErrorCode::InvalidArgument,
              "ResolveLinearSolverType: size must be >= 0, got " + std::to_string(size));
    return LinearSolverType::Auto;
  }
  if (requested != LinearSolverType::Auto) return requested;
#if SUPERDEX_HAS_CHOLMOD
  return size <= kDenseSolverMaxSize ? LinearSolverType::Dense : LinearSolverType::Cholmod;
#else
  (void)size;
  return LinearSolverType::Dense;
#endif
}

std::unique_ptr<LinearSolver> CreateLinearSolver(LinearSolverType type, PcgParams const& pcg,
                                                 Error& error) {
  switch (type) {
    case LinearSolverType::Auto:
      error.Set(ErrorCode::InvalidArgument,
                "CreateLinearSolver: type must be a concrete backend, got Auto; resolve it with "
                "ResolveLinearSolverType(type, size) first");
      return nullptr;
    case LinearSolverType::Cholmod:
#if SUPERDEX_HAS_CHOLMOD
      return std::make_unique<internal::CholmodSolver>();
#else
      error.Set(ErrorCode::NotSupported,
                "CreateLinearSolver: type Cholmod is not compiled into this build of SuperDex");
      return nullptr;
#endif
    case LinearSolverType::PetscPcg:
#if SUPERDEX_HAS_PETSC
      if (!ValidatePcgParams(pcg, error)) return nullptr;
      if (!internal::EnsurePetscInitialized(error)) return nullptr;
      return std::make_unique<internal::PetscPcgSolver>(pcg);
#else
      error.Set(ErrorCode::NotSupported,
                "CreateLinearSolver: type PetscPcg is not compiled into this build of SuperDex");
      return nullptr;
#endif
    case LinearSolverType::Dense:
      return std::make_unique<internal::DenseCholeskySolver>();
    case LinearSolverType::PetscMumps:
#if SUPERDEX_HAS_PETSC && defined(PETSC_HAVE_MUMPS)
      if (!internal::EnsurePetscInitialized(error)) return nullptr;
      return std::make_unique<internal::PetscMumpsSolver>();
#else
      error.Set(ErrorCode::NotSupported,
                "CreateLinearSolver: type PetscMumps is not compiled into this build of SuperDex "
                "(PETSc without MUMPS)");
      return nullptr;
#endif
  }
  error.Set(ErrorCode::InvalidArgument,
            "CreateLinearSolver: type must be a LinearSolverType, got the value " +
                std::to_string(static_cast<int>(type)));
  return nullptr;
}

}  // namespace superdex

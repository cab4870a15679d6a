#include <superdex/linsolve/petsc_mumps_solver.h>

#include <algorithm>
#include <string>

#include <petscmat.h>

#include <superdex/core/mpi.h>
#include <superdex/linsolve/petsc_distributed_matrix.h>
#include <superdex/linsolve/petsc_runtime.h>

namespace superdex::internal {

struct PetscMumpsSolver::Impl {
  Mat matrix = nullptr;    ///< SeqSBAIJ, A's upper triangle; or the distributed MPIAIJ (a reference)
  Mat factor = nullptr;    ///< MUMPS's factor, analyzed at Analyze
  IS order = nullptr;      ///< identity (PETSc's API asks for one): MUMPS orders A itself
  Vec rhs = nullptr;       ///< one rank: owns its storage; b is copied in
  Vec solution = nullptr;  ///< one rank: no storage of its own: wraps the caller's x
  int size = 0;
  /// SBAIJ value position of each upper CSC entry k of A (row i, column j)
  DynamicArray<PetscInt> slot;
  double factorNonzeros = -1, factorFlops = -1;
  /// SetDistribution; on more than one rank the matrix, its vectors and the
  /// gather of x are `distributed`'s
  RowDistribution distribution;
  PetscDistributedMatrix distributed;

  bool IsDistributed() const { return distribution.IsDistributed(); }
  LinearSolveResult FactorizeValues(SparseSymmetricMatrix const& a);

  void DestroyObjects() {
    if (IsPetscFinalized()) {  // PETSc is gone; so are its objects
      matrix = nullptr, factor = nullptr, order = nullptr, rhs = nullptr, solution = nullptr;
      distributed.Destroy();
      return;
    }
    MatDestroy(&factor);
    MatDestroy(&matrix);
    ISDestroy(&order);
    VecDestroy(&rhs);
    VecDestroy(&solution);
    distributed.Destroy();
  }
};

PetscMumpsSolver::PetscMumpsSolver() : impl_(new Impl) {}

PetscMumpsSolver::~PetscMumpsSolver() { impl_->DestroyObjects(); }

std::string PetscMumpsSolver::GetDescription() const {
  std::string text = "PETSc " + std::to_string(PETSC_VERSION_MAJOR) + "." +
                     std::to_string(PETSC_VERSION_MINOR) + "." + std::to_string(PETSC_VERSION_SUBMINOR) +
                     " MUMPS LDLᵀ";
  PetscInt ordering = 0;
  if (impl_->factor && MatMumpsGetInfog(impl_->factor, 7, &ordering) == 0) {
    // INFOG(7): the ordering MUMPS's analysis used
    char const* const names[] = {"AMD", "given", "AMF", "SCOTCH", "PORD", "METIS", "QAMD"};
    if (ordering >= 0 && ordering < 7) text += std::string(" (ordering ") + names[ordering] + ")";
  }
  if (impl_->IsDistributed()) text += " on " + std::to_string(impl_->distribution.GetNumRanks()) + " ranks";
  return text;
}

double PetscMumpsSolver::GetFactorNonzeros() const { return impl_->factorNonzeros; }

double PetscMumpsSolver::GetFactorFlops() const { return impl_->factorFlops; }

bool PetscMumpsSolver::DoSetDistribution(Communicator const& communicator, int rowBegin, int rowEnd) {
  impl_->distribution = {communicator, rowBegin, rowEnd};
  return true;
}

LinearSolveResult PetscMumpsSolver::DoAnalyze(SparseSymmetricMatrix const& a) {
  Impl& impl = *impl_;
  impl.DestroyObjects();
  impl.factorNonzeros = impl.factorFlops = -1;
  int const n = a.size;
  impl.size = n;
  if (n == 0) return {};

  if (impl.IsDistributed()) {
    // the MPIAIJ of the owned rows, both triangles, shared with the PCG
    // backend (PetscDistributedMatrix): PETSc's MUMPS interface takes the
    // upper triangle of an AIJ matrix for a Cholesky (LDLᵀ) factor itself,
    // and one matrix layout then serves both backends. MPISBAIJ would hold
    // half the entries but needs its own preallocation and block size 1
    if (LinearSolveResult created = impl.distributed.Create(a, impl.distribution); !created.Ok())
      return created;
    impl.matrix = impl.distributed.GetMatrix();
    SUPERDEX_PETSC(PetscObjectReference(reinterpret_cast<PetscObject>(impl.matrix)));
    SUPERDEX_PETSC(ISCreateStride(ToMpiComm(impl.distribution.communicator),
                                  impl.distribution.rowEnd - impl.distribution.rowBegin,
                                  impl.distribution.rowBegin, 1, &impl.order));
  } else {
    // row-wise upper triangle (SBAIJ) from A's column-wise upper triangle:
    // row i holds the entries (i, j ≥ i), in increasing j as the columns are
    // visited in order
    DynamicArray<PetscInt> rowStart(static_cast<std::size_t>(n) + 1, 0);
    for (int k = 0; k < a.colStart[n]; ++k) ++rowStart[a.rowIndex[k] + 1];
    for (int r = 0; r < n; ++r) rowStart[r + 1] += rowStart[r];
    DynamicArray<PetscInt> cursor(rowStart.begin(), rowStart.end() - 1);
    DynamicArray<PetscInt> columns(static_cast<std::size_t>(rowStart[n]));
    impl.slot.assign(a.rowIndex.size(), -1);
    for (int j = 0; j < n; ++j)
      for (int k = a.colStart[j]; k < a.colStart[j + 1]; ++k) {
        PetscInt const position = cursor[a.rowIndex[k]]++;
        columns[position] = j;
        impl.slot[k] = position;
      }

    SUPERDEX_PETSC(MatCreate(PETSC_COMM_SELF, &impl.matrix));
    SUPERDEX_PETSC(MatSetSizes(impl.matrix, n, n, n, n));
    SUPERDEX_PETSC(MatSetType(impl.matrix, MATSEQSBAIJ));
    SUPERDEX_PETSC(MatSeqSBAIJSetPreallocationCSR(impl.matrix, 1, rowStart.data(), columns.data(), nullptr));
    SUPERDEX_PETSC(MatSetOption(impl.matrix, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE));
    SUPERDEX_PETSC(MatCreateVecs(impl.matrix, &impl.solution, &impl.rhs));
    // the solution Vec only ever wraps the caller's x: free its own storage
    VecDestroy(&impl.solution);
    SUPERDEX_PETSC(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, n, nullptr, &impl.solution));
    SUPERDEX_PETSC(ISCreateStride(PETSC_COMM_SELF, n, 0, 1, &impl.order));
  }

  // MUMPS's analysis, on the pattern alone (the values are zeros yet):
  // SYM = 2 (LDLᵀ with pivoting; the matrix is not flagged SPD), its own
  // ordering of the plain graph (ICNTL(12) = 1: no compression by a matching
  // of the values), null pivots detected (ICNTL(24)) so that a singular
  // matrix shows in the inertia, nothing printed (ICNTL(1)–(4))
  SUPERDEX_PETSC(MatGetFactor(impl.matrix, MATSOLVERMUMPS, MAT_FACTOR_CHOLESKY, &impl.factor));
  SUPERDEX_PETSC(MatMumpsSetIcntl(impl.factor, 1, -1));
  SUPERDEX_PETSC(MatMumpsSetIcntl(impl.factor, 2, -1));
  SUPERDEX_PETSC(MatMumpsSetIcntl(impl.factor, 3, -1));
  SUPERDEX_PETSC(MatMumpsSetIcntl(impl.factor, 4, 0));
  SUPERDEX_PETSC(MatMumpsSetIcntl(impl.factor, 12, 1));
  SUPERDEX_PETSC(MatMumpsSetIcntl(impl.factor, 24, 1));
  // across ranks: the root front is factored by MUMPS itself rather than
  // ScaLAPACK (ICNTL(13) = 1), without which the inertia (INFOG(12)) does
  // not count the root's negative pivots and PETSc refuses MatGetInertia.
  // (PETSc 3.18.5 was seen to turn it on during the factorization itself on
  // 2 ranks; that is not documented, so it is set here.)
  if (impl.IsDistributed()) SUPERDEX_PETSC(MatMumpsSetIcntl(impl.factor, 13, 1));
  MatFactorInfo info;
  SUPERDEX_PETSC(MatFactorInfoInitialize(&info));
  SUPERDEX_PETSC(MatCholeskyFactorSymbolic(impl.factor, impl.matrix, impl.order, &info));
  PetscInt entries = 0;
  PetscReal flops = 0;
  SUPERDEX_PETSC(MatMumpsGetInfog(impl.factor, 20, &entries));
  SUPERDEX_PETSC(MatMumpsGetRinfog(impl.factor, 1, &flops));
  // INFOG(20) < 0 counts millions of entries
  impl.factorNonzeros = entries >= 0 ? static_cast<double>(entries) : -1e6 * static_cast<double>(entries);
  impl.factorFlops = flops;
  ++numObjectBuilds_;
  return {};
}

LinearSolveResult PetscMumpsSolver::DoFactorize(SparseSymmetricMatrix const& a) {
  Impl& impl = *impl_;
  if (impl.size == 0) return {};
  if (!impl.IsDistributed()) return impl.FactorizeValues(a);
  // MUMPS's outcome (INFOG, the inertia) is global already; a PETSc error is
  // this rank's: every rank returns the same result
  return AgreeOnResult(impl.distribution.communicator, impl.FactorizeValues(a));
}

LinearSolveResult PetscMumpsSolver::Impl::FactorizeValues(SparseSymmetricMatrix const& a) {
  if (IsDistributed()) {
    // the owned rows' values in place (PetscDistributedMatrix::SetValues)
    if (LinearSolveResult set = distributed.SetValues(a); !set.Ok()) return set;
  } else {
    // values in place
    PetscScalar* values = nullptr;
    SUPERDEX_PETSC(MatSeqSBAIJGetArray(matrix, &values));
    std::size_t const numEntries = a.values.size();
    for (std::size_t k = 0; k < numEntries; ++k) values[slot[k]] = a.values[k];
    SUPERDEX_PETSC(MatSeqSBAIJRestoreArray(matrix, &values));
  }

  MatFactorInfo info;
  SUPERDEX_PETSC(MatFactorInfoInitialize(&info));
  SUPERDEX_PETSC(MatCholeskyFactorNumeric(factor, matrix, &info));
  MatFactorError failed = MAT_FACTOR_NOERROR;
  SUPERDEX_PETSC(MatFactorGetError(factor, &failed));
  if (failed != MAT_FACTOR_NOERROR) {
    PetscInt status = 0;
    MatMumpsGetInfog(factor, 1, &status);
    MatFactorClearError(factor);
    // INFOG(1) = -10: numerically singular; the rest are MUMPS's own errors
    // (memory, integer overflow), not properties of A
    if (status == -10)
      return SolveFailure(LinearSolveStatus::NotPositiveDefinite,
                          "MUMPS: the matrix is numerically singular (INFOG(1) = -10)");
    return SolveFailure(LinearSolveStatus::BackendError,
                        "MUMPS numeric factorization failed: INFOG(1) = " + std::to_string(status));
  }
  PetscInt negative = 0, zero = 0, positive = 0;
  SUPERDEX_PETSC(MatGetInertia(factor, &negative, &zero, &positive));
  if (negative > 0 || zero > 0)
    return SolveFailure(LinearSolveStatus::NotPositiveDefinite,
                        "MUMPS: the matrix is not positive definite (" + std::to_string(negative) +
                            " negative and " + std::to_string(zero) + " null pivots of " +
                            std::to_string(size) + ")");
  return {};
}

LinearSolveResult PetscMumpsSolver::DoSolve(Span<real const> b, Span<real> x) {
  Impl& impl = *impl_;
  if (impl.size == 0) return {};
  if (impl.IsDistributed()) {
    // the owned entries of b in, all of x out on every rank
    if (LinearSolveResult set = impl.distributed.SetRhs(b); !set.Ok()) return set;
    if (LinearSolveResult solved = AgreeOnPetscCall(
            impl.distribution.communicator,
            MatSolve(impl.factor, impl.distributed.GetRhs(), impl.distributed.GetSolution()),
            "MatSolve (MUMPS)");
        !solved.Ok())
      return solved;
    return impl.distributed.GatherSolution(x);
  }
  PetscScalar* rhs = nullptr;
  SUPERDEX_PETSC(VecGetArrayWrite(impl.rhs, &rhs));
  std::copy(b.begin(), b.end(), rhs);
  SUPERDEX_PETSC(VecRestoreArrayWrite(impl.rhs, &rhs));
  SUPERDEX_PETSC(VecPlaceArray(impl.solution, x.data()));
  PetscErrorCode const code = MatSolve(impl.factor, impl.rhs, impl.solution);
  VecResetArray(impl.solution);
  if (code != 0)
    return SolveFailure(LinearSolveStatus::BackendError, "PETSc MatSolve (MUMPS) failed: " + PetscErrorText(code));
  return {};
}

}  // namespace superdex::internal

#include <superdex/linsolve/petsc_distributed_matrix.h>

#include <algorithm>
#include <numeric>
#include <string>

#include <petscmat.h>

#include <superdex/core/mpi.h>
#include <superdex/linsolve/petsc_runtime.h>

namespace superdex::internal {

PetscDistributedMatrix::~PetscDistributedMatrix() { Destroy(); }

void PetscDistributedMatrix::Destroy() {
  if (IsPetscFinalized()) {  // PETSc is gone; so are its objects
    matrix_ = nullptr, rhs_ = solution_ = gathered_ = nullptr, gather_ = nullptr;
    return;
  }
  VecScatterDestroy(&gather_);
  VecDestroy(&gathered_);
  VecDestroy(&solution_);
  VecDestroy(&rhs_);
  MatDestroy(&matrix_);
}

LinearSolveResult PetscDistributedMatrix::Create(SparseSymmetricMatrix const& a,
                                                 RowDistribution const& distribution) {
  Destroy();
  MPI_Comm const comm = ToMpiComm(distribution.communicator);
  int const n = a.size;
  size_ = n;
  rowBegin_ = distribution.rowBegin;
  rowEnd_ = distribution.rowEnd;

  // the ranges: each within [0, n], each beginning where the previous rank's
  // ends (PETSc's layout is the prefix sum of the local sizes), all adding
  // to n; refused on every rank when one rank's is wrong
  int const rank = distribution.communicator.GetRank();
  int const ownedRows = rowEnd_ - rowBegin_;
  int rowsBefore = 0, rowsInAll = 0;
  MPI_Exscan(&ownedRows, &rowsBefore, 1, MPI_INT, MPI_SUM, comm);
  if (rank == 0) rowsBefore = 0;  // MPI_Exscan leaves rank 0's result undefined
  MPI_Allreduce(&ownedRows, &rowsInAll, 1, MPI_INT, MPI_SUM, comm);
  LinearSolveResult checked;
  if (!(0 <= rowBegin_ && rowBegin_ <= rowEnd_ && rowEnd_ <= n) || rowBegin_ != rowsBefore ||
      rowsInAll != n)
    checked = SolveFailure(LinearSolveStatus::InvalidInput,
                           "SetDistribution: this rank's rows [" + std::to_string(rowBegin_) + ", " +
                               std::to_string(rowEnd_) + ") of a matrix of size " + std::to_string(n) +
                               " are not the contiguous range after the lower ranks' " +
                               std::to_string(rowsBefore) + " rows (the ranks own " +
                               std::to_string(rowsInAll) + " rows in all)");
  checked = AgreeOnResult(distribution.communicator, checked);
  if (!checked.Ok()) return checked;

  // block size: the gcd of A's DoF blocks (AMG aggregates whole nodes), where
  // every rank's range is a multiple of it (PETSc's layout requires it)
  int blockSize = 0;
  for (int size : a.blockSizes) blockSize = std::gcd(blockSize, size);
  if (blockSize <= 0 || n % blockSize != 0) blockSize = 1;
  int aligned = rowBegin_ % blockSize == 0 && rowEnd_ % blockSize == 0;
  MPI_Allreduce(MPI_IN_PLACE, &aligned, 1, MPI_INT, MPI_MIN, comm);
  blockSize_ = aligned ? blockSize : 1;

  // the DoF blocks inside the owned rows (point-block Jacobi, block Jacobi's
  // groups); blocks of 1 for one cut by the range
  ownedBlockSizes_.clear();
  if (a.blockSizes.empty()) {
    ownedBlockSizes_.assign(static_cast<std::size_t>(ownedRows), 1);
  } else {
    int start = 0;
    for (int size : a.blockSizes) {
      int const end = start + size;
      if (start >= rowBegin_ && end <= rowEnd_)
        ownedBlockSizes_.push_back(size);
      else
        for (int dof = std::max(start, rowBegin_); dof < std::min(end, rowEnd_); ++dof)
          ownedBlockSizes_.push_back(1);
      start = end;
    }
  }

  // the owned rows in CSR, both triangles, columns sorted within a row:
  // stored entry k = (i, j), i <= j, is (i, j) of row i and (j, i) of row
  // j. Since i <= j, no column before rowBegin holds an owned entry. Going
  // through the columns in order puts each row's entries in column order.
  auto const owned = [&](int row) { return rowBegin_ <= row && row < rowEnd_; };
  DynamicArray<PetscInt> rowStart(static_cast<std::size_t>(ownedRows) + 1, 0), csrColumns;
  for (int pass = 0; pass < 2; ++pass) {
    // pass 0 counts each row's entries, pass 1 places them
    DynamicArray<PetscInt> next(rowStart.begin(), rowStart.end() - 1);
    for (int j = rowBegin_; j < n; ++j)
      for (int k = a.colStart[j]; k < a.colStart[j + 1]; ++k) {
        int const i = a.rowIndex[k];
        auto const place = [&](int row, int column) {
          if (pass == 0) {
            ++rowStart[row - rowBegin_ + 1];
            return;
          }
          PetscInt const position = next[row - rowBegin_]++;
          csrColumns[position] = column;
          entrySource_[position] = k;
        };
        if (owned(i)) place(i, j);
        if (i != j && owned(j)) place(j, i);
      }
    if (pass == 0) {
      for (int r = 0; r < ownedRows; ++r) rowStart[r + 1] += rowStart[r];
      csrColumns.assign(static_cast<std::size_t>(rowStart[ownedRows]), 0);
      entrySource_.assign(csrColumns.size(), 0);
    }
  }
  entryValues_.assign(entrySource_.size(), 0);

  SUPERDEX_PETSC(MatCreate(comm, &matrix_));
  SUPERDEX_PETSC(MatSetSizes(matrix_, ownedRows, ownedRows, n, n));
  SUPERDEX_PETSC(MatSetBlockSize(matrix_, blockSize_));
  SUPERDEX_PETSC(MatSetType(matrix_, MATMPIAIJ));
  // with zeros: MUMPS's analysis at Analyze wants an assembled matrix
  SUPERDEX_PETSC(MatMPIAIJSetPreallocationCSR(matrix_, rowStart.data(), csrColumns.data(), entryValues_.data()));
  // symmetric, not flagged SPD (see PetscPcgSolver); owned rows only
  SUPERDEX_PETSC(MatSetOption(matrix_, MAT_SYMMETRIC, PETSC_TRUE));
  SUPERDEX_PETSC(MatSetOption(matrix_, MAT_SYMMETRY_ETERNAL, PETSC_TRUE));
  SUPERDEX_PETSC(MatSetOption(matrix_, MAT_NO_OFF_PROC_ENTRIES, PETSC_TRUE));
  SUPERDEX_PETSC(MatSetOption(matrix_, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE));

  // the vectors of the owned rows, and the gather of the solution onto every
  // rank into a vector that only ever wraps the caller's x
  SUPERDEX_PETSC(MatCreateVecs(matrix_, &solution_, &rhs_));
  Vec all = nullptr;
  SUPERDEX_PETSC(VecScatterCreateToAll(solution_, &gather_, &all));
  VecDestroy(&all);
  SUPERDEX_PETSC(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, n, nullptr, &gathered_));
  return {};
}

LinearSolveResult PetscDistributedMatrix::SetValues(SparseSymmetricMatrix const& a) {
  std::size_t const numEntries = entrySource_.size();
  for (std::size_t m = 0; m < numEntries; ++m) entryValues_[m] = a.values[entrySource_[m]];
  SUPERDEX_PETSC(MatUpdateMPIAIJWithArray(matrix_, entryValues_.data()));
  return {};
}

namespace {

// the owned entries of `from` into `to`'s local array
LinearSolveResult CopyOwned(Span<real const> from, int rowBegin, int rowEnd, Vec to) {
  PetscScalar* local = nullptr;
  SUPERDEX_PETSC(VecGetArrayWrite(to, &local));
  std::copy(from.begin() + rowBegin, from.begin() + rowEnd, local);
  SUPERDEX_PETSC(VecRestoreArrayWrite(to, &local));
  return {};
}

}  // namespace

LinearSolveResult PetscDistributedMatrix::SetRhs(Span<real const> b) {
  return CopyOwned(b, rowBegin_, rowEnd_, rhs_);
}

LinearSolveResult PetscDistributedMatrix::SetSolution(Span<real const> x) {
  return CopyOwned(x, rowBegin_, rowEnd_, solution_);
}

LinearSolveResult PetscDistributedMatrix::GatherSolution(Span<real> x) {
  SUPERDEX_PETSC(VecPlaceArray(gathered_, x.data()));
  PetscErrorCode code = VecScatterBegin(gather_, solution_, gathered_, INSERT_VALUES, SCATTER_FORWARD);
  if (code == 0) code = VecScatterEnd(gather_, solution_, gathered_, INSERT_VALUES, SCATTER_FORWARD);
  VecResetArray(gathered_);
  SUPERDEX_PETSC(code);
  return {};
}

LinearSolveResult AgreeOnResult(Communicator const& communicator, LinearSolveResult local) {
  MPI_Comm const comm = ToMpiComm(communicator);
  int const ranks = communicator.GetSize();
  int failing = local.Ok() ? ranks : communicator.GetRank();
  MPI_Allreduce(MPI_IN_PLACE, &failing, 1, MPI_INT, MPI_MIN, comm);
  if (failing == ranks) return local;

  // the lowest failing rank's result, on every rank
  int fields[5] = {static_cast<int>(local.status), local.failingColumn, local.iterations,
                   local.truncated ? 1 : 0, static_cast<int>(local.reason.size())};
  MPI_Bcast(fields, 5, MPI_INT, failing, comm);
  LinearSolveResult result;
  result.status = static_cast<LinearSolveStatus>(fields[0]);
  result.failingColumn = fields[1];
  result.iterations = fields[2];
  result.truncated = fields[3] != 0;
  result.relativeResidual = local.relativeResidual;
  MPI_Bcast(&result.relativeResidual, 1, MPI_DOUBLE, failing, comm);
  std::string reason = std::move(local.reason);
  reason.resize(static_cast<std::size_t>(fields[4]));
  MPI_Bcast(reason.data(), fields[4], MPI_CHAR, failing, comm);
  result.reason = "rank " + std::to_string(failing) + " of " + std::to_string(ranks) + ": " + reason;
  return result;
}

LinearSolveResult AgreeOnPetscCall(Communicator const& communicator, int code, std::string const& call) {
  LinearSolveResult local;
  if (code != 0)
    local = SolveFailure(LinearSolveStatus::BackendError, "PETSc " + call + " failed: " + PetscErrorText(code));
  return AgreeOnResult(communicator, std::move(local));
}

}  // namespace superdex::internal

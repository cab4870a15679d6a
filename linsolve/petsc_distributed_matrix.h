// PetscDistributedMatrix: the symmetric A of sparse_symmetric_matrix.h
// across the ranks of a communicator, as both PETSc backends solve with it
// when LinearSolver::SetDistribution gave them more than one rank
// (docs/distributed.md, docs/linear_solvers.md "Across MPI ranks").
//
// Layout. Rank r owns the contiguous rows [rowBegin, rowEnd) of the ordered
// A; the ranges are in rank order and cover [0, n). Only the entries of A
// with an owned row or column are read (the assembler stores no others on
// a rank of several, HessianAssembler::Analyze).
//
// Create (once per pattern, collective) builds a MATMPIAIJ with the owned
// rows, both triangles (row i gets (i, j) for every stored (min(i,j),
// max(i,j))), block size the gcd g of A's DoF blocks when every rank's range
// is a multiple of g (else 1). It is preallocated from the owned rows in
// CSR with sorted columns (MatMPIAIJSetPreallocationCSR), so no entry
// travels between ranks, and keeps a map from each CSR entry to A's CSC
// value index. SetValues (every Newton iteration) fills one value array
// through that map and hands it to MatUpdateMPIAIJWithArray: values in
// place, no search, no allocation. (Coordinate preallocation,
// MatSetPreallocationCOO, did the same with about 130 MB more per rank on
// the 133,623-DoF beam on 2 ranks: PETSc keeps its own maps per
// coordinate entry.) It also creates the right-hand side and solution vectors (the
// owned rows) and the gather of the solution onto every rank
// (VecScatterCreateToAll).
//
// The header carries no PETSc include (installed headers may not): the
// PETSc handles appear by their struct names, which is what PETSc's Mat,
// Vec and VecScatter are pointers to.
#pragma once

#include <string>

#include <superdex/core/communicator.h>
#include <superdex/core/types.h>
#include <superdex/linsolve/linear_solver.h>
#include <superdex/linsolve/sparse_symmetric_matrix.h>

struct _p_Mat;      // PETSc's Mat is _p_Mat*
struct _p_Vec;      // Vec
struct _p_PetscSF;  // VecScatter

namespace superdex::internal {

/// The ranks a backend solves on and this rank's rows (SetDistribution).
struct RowDistribution {
  Communicator communicator;
  int rowBegin = 0, rowEnd = 0;

  int GetNumRanks() const { return communicator.GetSize(); }
  /// More than one rank: the backend takes the distributed path.
  bool IsDistributed() const { return GetNumRanks() > 1; }
};

class PetscDistributedMatrix {
 public:
  PetscDistributedMatrix() = default;
  /// Destroys the PETSc objects (unless PETSc was already finalized).
  ~PetscDistributedMatrix();
  PetscDistributedMatrix(PetscDistributedMatrix const&) = delete;
  PetscDistributedMatrix& operator=(PetscDistributedMatrix const&) = delete;

  /// Collective, once per pattern: discards the previous objects and builds
  /// the matrix of A's pattern on `distribution`'s ranks, its vectors and the
  /// gather. The values are zero until SetValues. Returns InvalidInput on
  /// every rank when some rank's range is not within [0, n) or the ranges are
  /// not contiguous in rank order, BackendError when PETSc fails.
  LinearSolveResult Create(SparseSymmetricMatrix const& a, RowDistribution const& distribution);
  /// Collective: the owned rows' values of A (the analyzed pattern) into the
  /// matrix, in place (MatSetValuesCOO). Allocates nothing.
  LinearSolveResult SetValues(SparseSymmetricMatrix const& a);
  /// b's owned entries into the right-hand side vector (n entries in b; the
  /// others are not read). Local.
  LinearSolveResult SetRhs(Span<real const> b);
  /// x's owned entries into the solution vector (an initial guess). Local.
  LinearSolveResult SetSolution(Span<real const> x);
  /// Collective: the whole solution vector into x (n entries) on every rank.
  LinearSolveResult GatherSolution(Span<real> x);
  /// Destroys the PETSc objects (collective where they are).
  void Destroy();

  /// The MATMPIAIJ (owned by this object; PetscObjectReference to keep it).
  _p_Mat* GetMatrix() const { return matrix_; }
  _p_Vec* GetRhs() const { return rhs_; }
  _p_Vec* GetSolution() const { return solution_; }
  int GetBlockSize() const { return blockSize_; }
  int GetNumOwnedRows() const { return rowEnd_ - rowBegin_; }
  int GetRowBegin() const { return rowBegin_; }
  /// The DoF blocks within the owned rows, in order, adding to
  /// GetNumOwnedRows(): A's blocks, with blocks of 1 where A's blocks are
  /// unknown or one straddles the range's ends.
  Span<int const> GetOwnedBlockSizes() const { return ownedBlockSizes_; }

 private:
  _p_Mat* matrix_ = nullptr;
  _p_Vec* rhs_ = nullptr;       ///< owned rows, own storage
  _p_Vec* solution_ = nullptr;  ///< owned rows, own storage
  _p_Vec* gathered_ = nullptr;  ///< n entries, no storage of its own: wraps the caller's x
  _p_PetscSF* gather_ = nullptr;
  int size_ = 0, rowBegin_ = 0, rowEnd_ = 0, blockSize_ = 1;
  /// A's CSC value index of each entry of the owned rows' CSR (row by row,
  /// columns sorted: MatUpdateMPIAIJWithArray's order)
  DynamicArray<int> entrySource_;
  DynamicArray<real> entryValues_;     ///< the values of those entries
  DynamicArray<int> ownedBlockSizes_;
};

/// Collective on `communicator`: the same result on every rank. When every
/// rank's `local` result is Ok, returns it; else the lowest failing rank's
/// status, failing column and reason, with the rank named in the reason.
LinearSolveResult AgreeOnResult(Communicator const& communicator, LinearSolveResult local);

/// Collective: AgreeOnResult of a PETSc call's error code (`code`, a
/// PetscErrorCode): BackendError "PETSc <call> failed: <PETSc's message>"
/// on every rank when it failed on some rank, else Ok.
LinearSolveResult AgreeOnPetscCall(Communicator const& communicator, int code, std::string const& call);

}  // namespace superdex::internal

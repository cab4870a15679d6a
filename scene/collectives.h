// Internal: the few collective operations the stage solver needs across MPI
// ranks (docs/distributed.md, "Stage 1"). Every rank holds the whole scene;
// these keep what each rank computes for its own part, and every decision
// taken from it, the same on all ranks. (A linear solver's result is made
// the same on every rank by AgreeOnResult, petsc_distributed_matrix.h.)
#pragma once

#include <superdex/core/communicator.h>
#include <superdex/core/types.h>
#include <superdex/linsolve/reused_factor_cg.h>

namespace superdex::internal {

/// `ordered` holds this rank's rows [partRowStart[rank], partRowStart[rank+1])
/// of a vector in the partition-major order; afterwards every rank holds all
/// of it (MPI_Allgatherv in place). `counts` and `displacements` are scratch
/// of one entry per rank, sized once by the caller.
void AllgatherRows(Communicator const& communicator, DynamicArray<int> const& partRowStart,
                   DynamicArray<int>& counts, DynamicArray<int>& displacements, Span<real> ordered);

/// True on every rank when `value` is true on every rank (MPI_LAND).
bool OnAllRanks(Communicator const& communicator, bool value);

/// Each of `values` replaced by its sum over the ranks, added in rank order
/// so that every rank gets the same bits (MPI_Allgather, then the sums).
/// `scratch` holds at least values.size() entries per rank, sized by the
/// caller.
void SumInRankOrder(Communicator const& communicator, Span<real> values, DynamicArray<real>& scratch);

/// ReusedFactorCg's product across ranks: each rank multiplies its own rows
/// [partRowStart[rank], partRowStart[rank+1]) of the partition-major order
/// (MultiplySymmetricRows reads only the entries the rank has complete),
/// then AllgatherRows gives every rank all of y, the same bits everywhere.
class OwnedRowsProduct final : public MatrixProduct {
 public:
  /// `partRowStart` (one entry per rank and one more) must outlive the
  /// product; it is read at every Multiply, so a new partition needs no call.
  void Set(Communicator const& communicator, DynamicArray<int> const* partRowStart);
  void Multiply(SparseSymmetricMatrix const& a, Span<real const> x, Span<real> y) override;

 private:
  Communicator communicator_;
  DynamicArray<int> const* partRowStart_ = nullptr;
  DynamicArray<int> counts_, displacements_;  ///< MPI_Allgatherv scratch
};

}  // namespace superdex::internal

// Internal: the few collective operations the stage solver needs across MPI
// ranks (docs/distributed.md, "Stage 1"). Every rank holds the whole scene;
// these keep what each rank computes for its own part, and every decision
// taken from it, the same on all ranks. (A linear solver's result is made
// the same on every rank by AgreeOnResult, petsc_distributed_matrix.h.)
#pragma once

#include <superdex/core/communicator.h>
#include <superdex/core/types.h>

namespace superdex::internal {

/// `ordered` holds this rank's rows [partRowStart[rank], partRowStart[rank+1])
/// of a vector in the partition-major order; afterwards every rank holds all
/// of it (MPI_Allgatherv in place). `counts` and `displacements` are scratch
/// of one entry per rank, sized once by the caller.
void AllgatherRows(Communicator const& communicator, DynamicArray<int> const& partRowStart,
                   DynamicArray<int>& counts, DynamicArray<int>& displacements, Span<real> ordered);

/// True on every rank when `value` is true on every rank (MPI_LAND).
bool OnAllRanks(Communicator const& communicator, bool value);

/// The sum of every rank's `value`, added in rank order, so that every rank
/// gets the same bits (MPI_Allgather, then a sum). `scratch` holds one entry
/// per rank, sized by the caller.
real SumInRankOrder(Communicator const& communicator, real value, DynamicArray<real>& scratch);

}  // namespace superdex::internal

#include <superdex/scene/collectives.h>

#include <climits>

#include <superdex/core/mpi.h>

namespace superdex::internal {

void AllgatherRows(Communicator const& communicator, DynamicArray<int> const& partRowStart,
                   DynamicArray<int>& counts, DynamicArray<int>& displacements, Span<real> ordered) {
  int const ranks = static_cast<int>(partRowStart.size()) - 1;
  for (int r = 0; r < ranks; ++r) {
    displacements[r] = partRowStart[r];
    counts[r] = partRowStart[r + 1] - partRowStart[r];
  }
  MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, ordered.data(), counts.data(), displacements.data(),
                 MPI_DOUBLE, ToMpiComm(communicator));
}

void AgreeOnResult(Communicator const& communicator, LinearSolveResult& result) {
  MPI_Comm const comm = ToMpiComm(communicator);
  int failingRank = result.Ok() ? INT_MAX : communicator.GetRank();
  MPI_Allreduce(MPI_IN_PLACE, &failingRank, 1, MPI_INT, MPI_MIN, comm);
  if (failingRank == INT_MAX) return;
  // status, column, iterations, truncated, reason length; the residual
  int fields[5] = {static_cast<int>(result.status), result.failingColumn, result.iterations,
                   result.truncated ? 1 : 0, static_cast<int>(result.reason.size())};
  MPI_Bcast(fields, 5, MPI_INT, failingRank, comm);
  MPI_Bcast(&result.relativeResidual, 1, MPI_DOUBLE, failingRank, comm);
  result.status = static_cast<LinearSolveStatus>(fields[0]);
  result.failingColumn = fields[1];
  result.iterations = fields[2];
  result.truncated = fields[3] != 0;
  result.reason.resize(fields[4]);
  MPI_Bcast(result.reason.data(), fields[4], MPI_CHAR, failingRank, comm);
}

real SumInRankOrder(Communicator const& communicator, real value, DynamicArray<real>& scratch) {
  MPI_Allgather(&value, 1, MPI_DOUBLE, scratch.data(), 1, MPI_DOUBLE, ToMpiComm(communicator));
  real sum = 0;
  for (real v : scratch) sum += v;
  return sum;
}

}  // namespace superdex::internal

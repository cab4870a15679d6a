#include <superdex/core/communicator.h>

#include <superdex/core/mpi.h>
#include <superdex/core/mpi_runtime.h>

namespace superdex {

namespace {
bool MpiRunning() { return internal::IsMpiRunning(); }
}  // namespace

Communicator Communicator::World(Error& error) {
  if (!internal::EnsureMpiInitialized(error)) return Communicator();
  return ToCommunicator(MPI_COMM_WORLD);
}

int Communicator::GetSize() const {
  int size = 1;
  if (set_ && MpiRunning()) MPI_Comm_size(ToMpiComm(*this), &size);
  return size;
}

int Communicator::GetRank() const {
  int rank = 0;
  if (set_ && MpiRunning()) MPI_Comm_rank(ToMpiComm(*this), &rank);
  return rank;
}

}  // namespace superdex

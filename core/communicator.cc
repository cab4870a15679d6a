#include <superdex/core/communicator.h>

#include <superdex/core/mpi.h>
#include <superdex/linsolve/petsc_runtime.h>

namespace superdex {

namespace {
bool MpiRunning() {
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  return initialized && !finalized;
}
}  // namespace

Communicator Communicator::World(Error& error) {
  if (!MpiRunning() && !internal::EnsurePetscInitialized(error)) return Communicator();
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

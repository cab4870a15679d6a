#include <superdex/core/communicator.h>

#include <superdex/core/mpi.h>
#include <superdex/core/mpi_runtime.h>

#include <string>

namespace superdex {

namespace {
bool MpiRunning() { return internal::IsMpiRunning(); }

/// MPI_Comm_f2c's communicator for `handle`, or false where it names none:
/// MPI_COMM_NULL, or an invalid C handle (Open MPI's null pointer for a
/// handle past its table or of a freed communicator; MPICH has no handle 0)
bool ToValidComm(int handle, MPI_Comm& comm) {
  comm = MPI_Comm_f2c(static_cast<MPI_Fint>(handle));
  return comm != MPI_COMM_NULL && comm != MPI_Comm{};
}
}  // namespace

bool Communicator::Check(std::string const& field, Error& error) const {
  if (!set_) return true;
  if (!MpiRunning()) {
    error.Set(ErrorCode::InvalidArgument, field + " has Fortran handle " + std::to_string(handle_) +
                                              " but MPI is not running (start it with Communicator::World, "
                                              "or MPI_Init before making the handle)");
    return false;
  }
  MPI_Comm comm;
  if (!ToValidComm(handle_, comm)) {
    error.Set(ErrorCode::InvalidArgument, field + " has Fortran handle " + std::to_string(handle_) +
                                              ", which is not a communicator of this process "
                                              "(MPI_Comm_f2c gives no valid communicator)");
    return false;
  }
  return true;
}

Communicator Communicator::World(Error& error) {
  if (!internal::EnsureMpiInitialized(error)) return Communicator();
  return ToCommunicator(MPI_COMM_WORLD);
}

int Communicator::GetSize() const {
  int size = 1;
  MPI_Comm comm;
  if (set_ && MpiRunning() && ToValidComm(handle_, comm)) MPI_Comm_size(comm, &size);
  return size;
}

int Communicator::GetRank() const {
  int rank = 0;
  MPI_Comm comm;
  if (set_ && MpiRunning() && ToValidComm(handle_, comm)) MPI_Comm_rank(comm, &rank);
  return rank;
}

}  // namespace superdex

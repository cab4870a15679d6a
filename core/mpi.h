// Conversions between superdex::Communicator and MPI_Comm, for programs that
// use MPI themselves (this header includes mpi.h; the rest of SuperDex's
// headers do not).
#pragma once

#include <mpi.h>

#include <superdex/core/communicator.h>

namespace superdex {

inline Communicator ToCommunicator(MPI_Comm comm) {
  return Communicator::FromFortranHandle(static_cast<int>(MPI_Comm_c2f(comm)));
}

/// MPI_COMM_SELF for the one-process default.
inline MPI_Comm ToMpiComm(Communicator const& communicator) {
  return communicator.IsSet() ? MPI_Comm_f2c(static_cast<MPI_Fint>(communicator.GetFortranHandle()))
                              : MPI_COMM_SELF;
}

}  // namespace superdex

// The MPI processes (ranks) a scene runs on (docs/distributed.md).
//
// SuperDex's public headers carry no mpi.h: a communicator is held by its
// Fortran handle (MPI_Comm_c2f), which every MPI implementation defines as an
// integer. <superdex/core/mpi.h> converts from and to MPI_Comm for programs
// that include mpi.h themselves. The default Communicator is one process: no
// MPI call is made with it, and everything runs as in a program without MPI.
#pragma once

#include <superdex/core/error.h>

#include <string>

namespace superdex {

class Communicator {
 public:
  /// One process (no MPI).
  Communicator() = default;

  /// MPI_COMM_WORLD. Initializes MPI (through PETSc) when the program has not;
  /// under `mpirun -n R` that is the R ranks of the job. Returns the one-process
  /// communicator and sets `error` (BackendError) when MPI cannot start.
  static Communicator World(Error& error);
  /// The communicator with Fortran handle `handle` (MPI_Comm_c2f of an
  /// MPI_Comm the program keeps valid while SuperDex uses it).
  static Communicator FromFortranHandle(int handle) { return Communicator(handle); }

  /// False for the one-process default.
  bool IsSet() const { return set_; }
  int GetFortranHandle() const { return handle_; }
  /// MPI_Comm_size (1 for the default, when MPI is not initialized, or for
  /// a handle that names no communicator: see Check).
  int GetSize() const;
  /// MPI_Comm_rank (0 for the default, when MPI is not initialized, or for
  /// a handle that names no communicator).
  int GetRank() const;

  /// True for the default, or where MPI runs and MPI_Comm_f2c turns the
  /// handle into a communicator; otherwise false with InvalidArgument naming
  /// `field` and the handle. Scene::Create checks SceneParams::communicator.
  bool Check(std::string const& field, Error& error) const;

 private:
  explicit Communicator(int handle) : set_(true), handle_(handle) {}
  bool set_ = false;
  int handle_ = 0;
};

}  // namespace superdex

// PETSc's process-wide lifetime, as the PCG backend needs it.
//
// PETSc is initialized once per process, on the first PCG solver created,
// and finalized once:
//   - when SuperDex started MPI (through PetscInitialize), at process exit
//     (std::atexit), which also finalizes MPI;
//   - when the host program had already initialized MPI, just before the host
//     calls MPI_Finalize (an attribute delete callback on MPI_COMM_SELF, which
//     MPI_Finalize runs first), or at exit if the host never finalizes MPI;
//   - when the host program had already initialized PETSc itself, never: the
//     host owns PETSc's lifetime.
// PETSc's signal handlers are not installed (SuperDex never takes over the
// host's signals) and PETSc errors are returned as codes, not printed: the
// backend turns them into LinearSolveResult reasons.
//
// Solver objects that outlive PetscFinalize (a static Scene) skip their PETSc
// destroy calls: IsPetscFinalized() tells them.
#pragma once

#include <superdex/core/error.h>

namespace superdex::internal {

/// Initializes PETSc on the first call (thread-safe); later calls return the
/// first call's outcome. Returns false with kBackendError naming PETSc's
/// message when initialization failed.
bool EnsurePetscInitialized(Error& error);

/// True once PETSc has been finalized (by SuperDex or the host).
bool IsPetscFinalized();

}  // namespace superdex::internal

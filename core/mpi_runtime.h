// MPI's process-wide start, where SuperDex needs it and the host has not
// started it (Communicator::World).
//
// MPI is initialized once, at MPI_THREAD_FUNNELED (the level PETSc asks for:
// only the thread that called it makes MPI calls), and finalized at process
// exit. A host that started MPI itself owns it: SuperDex never finalizes it.
// PETSc, started later by the first PETSc solver (linsolve/petsc_runtime.h),
// finds MPI running and finalizes itself before MPI is.
#pragma once

#include <superdex/core/error.h>

namespace superdex::internal {

/// True when MPI is initialized and not yet finalized.
bool IsMpiRunning();

/// Initializes MPI on the first call where it is not running (thread-safe);
/// later calls return the first call's outcome. False with BackendError and
/// MPI's message when MPI cannot be initialized (or was already finalized).
bool EnsureMpiInitialized(Error& error);

}  // namespace superdex::internal

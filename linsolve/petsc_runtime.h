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

#include <string>

#include <superdex/core/error.h>
#include <superdex/linsolve/linear_solver.h>

namespace superdex::internal {

/// Initializes PETSc on the first call (thread-safe); later calls return the
/// first call's outcome. Returns false with BackendError naming PETSc's
/// message when initialization failed.
bool EnsurePetscInitialized(Error& error);

/// True once PETSc has been finalized (by SuperDex or the host).
bool IsPetscFinalized();

/// PETSc's message for an error code (PetscErrorMessage).
std::string PetscErrorText(int code);

/// A result of `status` with `reason`.
LinearSolveResult SolveFailure(LinearSolveStatus status, std::string reason);

}  // namespace superdex::internal

/// In the PETSc backends' .cc files (PETSc's headers included): returns a
/// BackendError result naming the PETSc call when it fails.
#define SUPERDEX_PETSC(call)                                                                   \
  do {                                                                                         \
    if (PetscErrorCode const code_ = (call); code_ != 0)                                       \
      return ::superdex::internal::SolveFailure(                                               \
          ::superdex::LinearSolveStatus::BackendError,                                         \
          std::string("PETSc ") + #call + " failed: " + ::superdex::internal::PetscErrorText(code_)); \
  } while (false)

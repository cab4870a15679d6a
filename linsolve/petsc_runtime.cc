#include <superdex/linsolve/petsc_runtime.h>

#include <cstdlib>
#include <mutex>
#include <string>

#include <mpi.h>
#include <petscsys.h>

namespace superdex::internal {

namespace {

struct PetscRuntime {
  std::once_flag once;
  bool ok = false;
  std::string message;
  bool ownsPetsc = false;  ///< SuperDex called PetscInitialize
};

PetscRuntime& Runtime() {
  static PetscRuntime runtime;
  return runtime;
}

// Finalizes PETSc if SuperDex initialized it and nobody finalized it yet. MPI
// must still be usable (PetscFinalize frees communicators).
void FinalizeOwnedPetsc() {
  if (!Runtime().ownsPetsc) return;
  Runtime().ownsPetsc = false;
  PetscBool finalized = PETSC_FALSE;
  PetscFinalized(&finalized);
  int mpiFinalized = 0;
  MPI_Finalized(&mpiFinalized);
  if (!finalized && !mpiFinalized) PetscFinalize();
}

// MPI_Finalize deletes MPI_COMM_SELF's attributes before anything else: the
// one moment PETSc can still be finalized cleanly in a host-owned MPI.
int FinalizeBeforeMpi(MPI_Comm, int, void*, void*) {
  FinalizeOwnedPetsc();
  return MPI_SUCCESS;
}

void Initialize(PetscRuntime& runtime) {
  PetscBool petscInitialized = PETSC_FALSE;
  PetscInitialized(&petscInitialized);
  if (petscInitialized) {  // the host owns PETSc
    runtime.ok = true;
    return;
  }
  int mpiInitialized = 0;
  MPI_Initialized(&mpiInitialized);

  // options set before PetscInitialize are kept by it
  PetscOptionsSetValue(nullptr, "-no_signal_handler", nullptr);
  PetscErrorCode const code = PetscInitializeNoArguments();
  if (code != 0) {
    char const* text = nullptr;
    PetscErrorMessage(code, &text, nullptr);
    runtime.message = "PETSc initialization failed: PetscInitialize returned " +
                      std::to_string(static_cast<int>(code)) + " (" + (text ? text : "?") + ")";
    return;
  }
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
  runtime.ownsPetsc = true;
  runtime.ok = true;

  if (mpiInitialized) {
    int keyval = MPI_KEYVAL_INVALID;
    if (MPI_Comm_create_keyval(MPI_COMM_NULL_COPY_FN, FinalizeBeforeMpi, &keyval, nullptr) ==
        MPI_SUCCESS)
      MPI_Comm_set_attr(MPI_COMM_SELF, keyval, nullptr);
  }
  std::atexit(FinalizeOwnedPetsc);
}

}  // namespace

bool EnsurePetscInitialized(Error& error) {
  PetscRuntime& runtime = Runtime();
  std::call_once(runtime.once, Initialize, std::ref(runtime));
  if (!runtime.ok) error.Set(ErrorCode::BackendError, runtime.message);
  return runtime.ok;
}

bool IsPetscFinalized() {
  PetscBool finalized = PETSC_FALSE;
  PetscFinalized(&finalized);
  return finalized == PETSC_TRUE;
}

std::string PetscErrorText(int code) {
  char const* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  return text ? text : "unknown PETSc error";
}

LinearSolveResult SolveFailure(LinearSolveStatus status, std::string reason) {
  LinearSolveResult result;
  result.status = status;
  result.reason = std::move(reason);
  return result;
}

}  // namespace superdex::internal

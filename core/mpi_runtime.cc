#include <superdex/core/mpi_runtime.h>

#include <cstdlib>
#include <mutex>
#include <string>

#include <mpi.h>

namespace superdex::internal {

namespace {
struct MpiRuntime {
  std::once_flag once;
  bool ok = false;
  std::string message;
};

MpiRuntime& Runtime() {
  static MpiRuntime runtime;
  return runtime;
}

// Finalizes MPI at exit where SuperDex initialized it and nobody finalized it
void FinalizeOwnedMpi() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized) MPI_Finalize();
}

void Initialize(MpiRuntime& runtime) {
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  if (finalized) {
    runtime.message = "MPI was already finalized in this process: it cannot be started again";
    return;
  }
  if (initialized) {  // the host owns MPI
    runtime.ok = true;
    return;
  }
  int provided = MPI_THREAD_SINGLE;
  int const code = MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  if (code != MPI_SUCCESS) {
    char text[MPI_MAX_ERROR_STRING] = {};
    int length = 0;
    MPI_Error_string(code, text, &length);
    runtime.message = "MPI initialization failed: MPI_Init_thread returned " + std::to_string(code) + " (" +
                      std::string(text, static_cast<std::size_t>(length)) + ")";
    return;
  }
  runtime.ok = true;
  std::atexit(FinalizeOwnedMpi);
}
}  // namespace

bool IsMpiRunning() {
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  return initialized && !finalized;
}

bool EnsureMpiInitialized(Error& error) {
  MpiRuntime& runtime = Runtime();
  std::call_once(runtime.once, Initialize, std::ref(runtime));
  if (!runtime.ok) error.Set(ErrorCode::BackendError, runtime.message);
  return runtime.ok;
}

}  // namespace superdex::internal

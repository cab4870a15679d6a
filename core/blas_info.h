// Which BLAS this process really runs, and whether its kernels suit the CPU.
//
// SuperDex does not link a BLAS itself: CHOLMOD loads libblas.so.3, i.e.
// whatever Debian's `libblas.so.3-<multiarch>` alternative points to
// (scripts/setup.sh selects OpenBLAS). GetBlasInfo therefore asks the loaded
// library at run time (dlsym on `openblas_get_config`, ...) rather than
// reporting what was found at build time.
//
// OpenBLAS 0.3.21 (Debian bookworm) picks its kernels from the CPU id; a CPU
// it maps to an older core, or a stray OPENBLAS_CORETYPE, runs far below the
// hardware: on an AVX-512 machine DGEMM ran at ~23 GFLOP/s per core with the
// SSE3 "Prescott" kernels, ~62 with "Haswell" (AVX2) and ~104 with "SkylakeX"
// (AVX-512). Setting OPENBLAS_CORETYPE before the process starts fixes it;
// `source scripts/env.sh` does that. See docs/blas.md.
#pragma once

#include <string>

namespace superdex {

struct BlasInfo {
  /// The library that provides the dgemm_ this process calls: "OpenBLAS",
  /// "Intel MKL", "BLIS", "reference BLAS or unknown (no openblas_get_config
  /// symbol)", or "none loaded (no dgemm_ symbol in this process)".
  std::string library;
  /// The library's own configuration string, e.g. "OpenBLAS 0.3.21
  /// NO_LAPACKE DYNAMIC_ARCH NO_AFFINITY SkylakeX MAX_THREADS=64"; for an
  /// unidentified library, "dgemm_ from <path>".
  std::string config;
  /// The kernel set in use ("SkylakeX", "Haswell", "Prescott", ...); empty
  /// when the library does not report one.
  std::string coreName;
  /// Threads the BLAS will use (openblas_get_num_threads); 1 when unknown.
  int numThreads = 1;
  /// The CPU has AVX-512 F, BW, DQ, VL and CD (what OpenBLAS's SkylakeX
  /// kernels need).
  bool cpuHasAvx512 = false;
  /// False when the kernels in use are of an older instruction-set tier than
  /// the CPU supports (e.g. Prescott or Haswell on an AVX-512 CPU), or when no
  /// optimised BLAS was identified.
  bool fastKernels = false;
  /// What to do when fastKernels is false; empty otherwise.
  std::string advice;
};

/// Inspects the BLAS loaded into this process. Never fails; fields it cannot
/// determine are left empty (see each field).
BlasInfo GetBlasInfo();

namespace internal {
/// The threads OpenBLAS runs its kernels on when it loaded
/// (OPENBLAS_NUM_THREADS, else every CPU); 1 for other BLAS libraries.
int BlasStartThreads();
/// Sets OpenBLAS's thread count (openblas_set_num_threads) when it differs
/// from the last count set here; a no-op for other BLAS libraries. The
/// factorizations choose it by their size (CholmodSolver).
void SetBlasThreads(int numThreads);
}  // namespace internal

}  // namespace superdex

// superdex_blas_info [n]: which BLAS this process runs and how fast.
//
// Prints superdex::GetBlasInfo() (the library, kernels and threads the
// loaded BLAS itself reports) and the measured DGEMM rate C = A·B on n×n
// matrices (default 2000), on one thread and on all threads. The thread
// count is set through openblas_set_num_threads when the library has it.
#include <superdex/core/blas_info.h>

#include <dlfcn.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

extern "C" void dgemm_(char const* transa, char const* transb, int const* m, int const* n,
                       int const* k, double const* alpha, double const* a, int const* lda,
                       double const* b, int const* ldb, double const* beta, double* c,
                       int const* ldc);

namespace {

struct GemmResult {
  double gflops = 0.0;
  int repetitions = 0;
  double maxError = 0.0;  // largest |C_ij - exact| over a few checked entries
};

// Times C = A·B, repeated until at least a second has passed (after one
// warm-up call), and checks a few entries against a direct dot product.
GemmResult MeasureDgemm(int n) {
  std::vector<double> a(static_cast<size_t>(n) * n), b(a.size()), c(a.size());
  for (size_t i = 0; i < a.size(); ++i) {
    a[i] = 1.0 / static_cast<double>(i % 7 + 1);
    b[i] = 1.0 / static_cast<double>(i % 5 + 1) - 0.3;
  }
  double const one = 1.0, zero = 0.0;
  auto gemm = [&] {
    dgemm_("N", "N", &n, &n, &n, &one, a.data(), &n, b.data(), &n, &zero, c.data(), &n);
  };

  // warm-up: thread pool start, page faults
  gemm();

  GemmResult result;
  using Clock = std::chrono::steady_clock;
  auto const start = Clock::now();
  double seconds = 0.0;
  do {
    gemm();
    ++result.repetitions;
    seconds = std::chrono::duration<double>(Clock::now() - start).count();
  } while (seconds < 1.0);
  result.gflops = 2.0 * n * n * static_cast<double>(n) * result.repetitions / seconds * 1e-9;

  // spot-check column-major entries C(i,j) = Σ_k A(i,k) B(k,j)
  for (int i : {0, n / 3, n - 1}) {
    for (int j : {0, n / 2, n - 1}) {
      double exact = 0.0;
      for (int k = 0; k < n; ++k) {
        exact += a[static_cast<size_t>(k) * n + i] * b[static_cast<size_t>(j) * n + k];
      }
      double const got = c[static_cast<size_t>(j) * n + i];
      result.maxError = std::max(result.maxError, std::abs(got - exact));
    }
  }
  return result;
}

std::string CpuModel() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0) {
      auto const colon = line.find(':');
      if (colon != std::string::npos) return line.substr(colon + 2);
    }
  }
  return "unknown";
}

}  // namespace

int main(int argc, char** argv) {
  int const n = argc > 1 ? std::atoi(argv[1]) : 2000;
  if (n <= 0) {
    std::fprintf(stderr, "usage: superdex_blas_info [n > 0], got '%s'\n", argv[1]);
    return 2;
  }

  superdex::BlasInfo const info = superdex::GetBlasInfo();
  char const* coretype = std::getenv("OPENBLAS_CORETYPE");
  std::printf("cpu                 %s (%u hardware threads)\n", CpuModel().c_str(),
              std::thread::hardware_concurrency());
  std::printf("cpu has AVX-512     %s\n", info.cpuHasAvx512 ? "yes" : "no");
  std::printf("OPENBLAS_CORETYPE   %s\n", coretype != nullptr ? coretype : "(unset)");
  std::printf("library             %s\n", info.library.c_str());
  std::printf("config              %s\n", info.config.empty() ? "-" : info.config.c_str());
  std::printf("core                %s\n", info.coreName.empty() ? "-" : info.coreName.c_str());
  std::printf("threads             %d\n", info.numThreads);
  std::printf("fast kernels        %s\n", info.fastKernels ? "yes" : "NO");
  if (!info.advice.empty()) std::printf("advice              %s\n", info.advice.c_str());

  // thread counts to measure: 1 and all, when the library lets us choose
  using SetThreads = void (*)(int);
  auto const setThreads =
      reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  std::vector<int> threadCounts;
  if (setThreads != nullptr) {
    threadCounts.push_back(1);
    if (info.numThreads > 1) threadCounts.push_back(info.numThreads);
  } else {
    threadCounts.push_back(info.numThreads);
  }

  bool ok = true;
  for (int threads : threadCounts) {
    if (setThreads != nullptr) setThreads(threads);
    GemmResult const r = MeasureDgemm(n);
    std::printf("dgemm n=%d threads=%d  %8.1f GFLOP/s (%d reps, max error %.1e)\n", n, threads,
                r.gflops, r.repetitions, r.maxError);
    if (!(r.maxError <= 1e-9 * n)) ok = false;
  }
  if (setThreads != nullptr) setThreads(info.numThreads);
  if (!ok) {
    std::fprintf(stderr, "superdex_blas_info: DGEMM result is wrong\n");
    return 1;
  }
  return 0;
}

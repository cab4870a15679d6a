#include <superdex/core/blas_info.h>

#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdlib>
#include <string_view>

namespace superdex {
namespace internal {
namespace {

// Instruction-set tiers, in the order OpenBLAS's kernels use them.
enum class SimdTier { Sse = 0, Avx = 1, Avx2 = 2, Avx512 = 3 };

// The best tier this CPU (and OS) supports.
SimdTier CpuTier() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
      __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl") &&
      __builtin_cpu_supports("avx512cd")) {
    return SimdTier::Avx512;
  }
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return SimdTier::Avx2;
  if (__builtin_cpu_supports("avx")) return SimdTier::Avx;
#endif
  return SimdTier::Sse;
}

// The tier of an OpenBLAS (0.3.x) x86 core name. Names not listed (other
// architectures, cores added after 0.3.21) count as the best tier, so they
// never trigger advice.
SimdTier CoreTier(std::string_view core) {
  auto in = [&](auto const& names) {
    for (std::string_view name : names) {
      if (core.size() == name.size() &&
          std::equal(core.begin(), core.end(), name.begin(), [](char a, char b) {
            return std::tolower(static_cast<unsigned char>(a)) ==
                   std::tolower(static_cast<unsigned char>(b));
          })) {
        return true;
      }
    }
    return false;
  };
  static constexpr std::array<std::string_view, 3> kAvx512 = {"SkylakeX", "Cooperlake",
                                                              "SapphireRapids"};
  static constexpr std::array<std::string_view, 3> kAvx2 = {"Haswell", "Zen", "Excavator"};
  static constexpr std::array<std::string_view, 4> kAvx = {"Sandybridge", "Bulldozer", "Piledriver",
                                                           "Steamroller"};
  static constexpr std::array<std::string_view, 14> kSse = {
      "Prescott",     "Core2",     "Penryn", "Dunnington", "Nehalem",    "Atom",      "Opteron",
      "Opteron_SSE3", "Barcelona", "Bobcat", "Katmai",     "Coppermine", "Northwood", "Banias"};
  if (in(kAvx512)) return SimdTier::Avx512;
  if (in(kAvx2)) return SimdTier::Avx2;
  if (in(kAvx)) return SimdTier::Avx;
  if (in(kSse)) return SimdTier::Sse;
  return SimdTier::Avx512;
}

// The OPENBLAS_CORETYPE value that selects the best kernels of a tier.
std::string_view CoreTypeFor(SimdTier tier) {
  switch (tier) {
    case SimdTier::Avx512:
      return "SkylakeX";
    case SimdTier::Avx2:
      return "Haswell";
    case SimdTier::Avx:
      return "Sandybridge";
    case SimdTier::Sse:
      break;
  }
  return "";
}

// Where to look the BLAS's own symbols up: the shared object that provides
// the dgemm_ this process calls, together with its dependencies. Debian's
// OpenBLAS libblas.so.3 is a thin library over libopenblas.so.0, so its
// handle reaches openblas_get_config, while the reference libblas.so.3 does
// not, even when OpenBLAS's liblapack.so.3 loaded libopenblas.so.0 too.
class BlasSymbols {
 public:
  BlasSymbols() {
    void* const dgemm = dlsym(RTLD_DEFAULT, "dgemm_");
    Dl_info where{};
    if (dgemm != nullptr && dladdr(dgemm, &where) != 0 && where.dli_fname != nullptr) {
      providerPath_ = where.dli_fname;
      handle_ = dlopen(where.dli_fname, RTLD_LAZY | RTLD_NOLOAD);
    }
  }
  ~BlasSymbols() {
    if (handle_ != nullptr) dlclose(handle_);
  }
  BlasSymbols(BlasSymbols const&) = delete;
  BlasSymbols& operator=(BlasSymbols const&) = delete;

  /// The function `name` of the BLAS in use, or nullptr.
  template <class Fn>
  Fn Find(char const* name) const {
    return reinterpret_cast<Fn>(dlsym(handle_ != nullptr ? handle_ : RTLD_DEFAULT, name));
  }

  /// The file that provides dgemm_ as the loader opened it; empty if none.
  std::string const& ProviderPath() const { return providerPath_; }

 private:
  void* handle_ = nullptr;
  std::string providerPath_;
};

/// OpenBLAS's thread controls, looked up once.
struct BlasThreadControl {
  BlasThreadControl() {
    BlasSymbols const blas;
    set = blas.Find<void (*)(int)>("openblas_set_num_threads");
    if (auto const get = blas.Find<int (*)()>("openblas_get_num_threads")) startThreads = std::max(1, get());
    current = startThreads;
  }
  void (*set)(int) = nullptr;
  int startThreads = 1;
  int current = 1;
};

BlasThreadControl& ThreadControl() {
  static BlasThreadControl control;
  return control;
}

}  // namespace

int BlasStartThreads() { return ThreadControl().startThreads; }

void SetBlasThreads(int numThreads) {
  BlasThreadControl& control = ThreadControl();
  numThreads = std::max(1, numThreads);
  if (!control.set || numThreads == control.current) return;
  control.set(numThreads);
  control.current = numThreads;
}

}  // namespace internal

BlasInfo GetBlasInfo() {
  using namespace internal;
  BlasInfo info;
  SimdTier const cpuTier = CpuTier();
  info.cpuHasAvx512 = cpuTier == SimdTier::Avx512;
  BlasSymbols const blas;

  // OpenBLAS: what libblas.so.3 (loaded by CHOLMOD) is when setup.sh ran
  if (auto const openblasConfig = blas.Find<char* (*)()>("openblas_get_config")) {
    info.library = "OpenBLAS";
    info.config = openblasConfig();
    if (auto const corename = blas.Find<char* (*)()>("openblas_get_corename")) {
      info.coreName = corename();
    }
    if (auto const numThreads = blas.Find<int (*)()>("openblas_get_num_threads")) {
      info.numThreads = numThreads();
    }
    info.fastKernels = info.coreName.empty() || CoreTier(info.coreName) >= cpuTier;
    if (!info.fastKernels) {
      std::string const wanted(CoreTypeFor(cpuTier));
      info.advice = "OpenBLAS runs its " + info.coreName + " kernels but this CPU can run the " +
                    "faster " + wanted + " ones; ";
      if (char const* preset = std::getenv("OPENBLAS_CORETYPE")) {
        info.advice += "OPENBLAS_CORETYPE is set to '" + std::string(preset) +
                       "': export OPENBLAS_CORETYPE=" + wanted +
                       " (or unset it and source scripts/env.sh) before starting the program";
      } else {
        info.advice += "export OPENBLAS_CORETYPE=" + wanted +
                       " (or source scripts/env.sh) before starting the program";
      }
    }
    return info;
  }

  // other optimised libraries the libblas.so.3 alternative may point to
  if (auto const mklVersion = blas.Find<void (*)(char*, int)>("MKL_Get_Version_String")) {
    std::array<char, 256> buffer{};
    mklVersion(buffer.data(), static_cast<int>(buffer.size()));
    info.library = "Intel MKL";
    info.config = buffer.data();
    if (auto const maxThreads = blas.Find<int (*)()>("MKL_Get_Max_Threads")) {
      info.numThreads = maxThreads();
    }
    info.fastKernels = true;
    return info;
  }
  if (auto const blisVersion = blas.Find<char const* (*)()>("bli_info_get_version_str")) {
    info.library = "BLIS";
    info.config = std::string("BLIS ") + blisVersion();
    if (auto const numThreads = blas.Find<long (*)()>("bli_thread_get_num_threads")) {
      info.numThreads = static_cast<int>(numThreads());
    }
    info.fastKernels = true;
    return info;
  }

  if (blas.ProviderPath().empty()) {
    info.library = "none loaded (no dgemm_ symbol in this process)";
    info.fastKernels = false;
    info.advice =
        "no BLAS is loaded: this program does not link CHOLMOD (e.g. a static SuperDex whose "
        "solvers it does not use)";
    return info;
  }
  info.library = "reference BLAS or unknown (no openblas_get_config symbol)";
  info.config = "dgemm_ from " + blas.ProviderPath();
  info.fastKernels = false;
  info.advice =
      "no optimised BLAS identified (Debian's reference BLAS runs DGEMM ~15x slower than "
      "OpenBLAS); run scripts/setup.sh, which installs libopenblas0-pthread and selects it "
      "with update-alternatives";
  return info;
}

}  // namespace superdex

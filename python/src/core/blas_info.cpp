// core/blas_info.h: which BLAS this process really runs.
#include "defines.h"

namespace superdex::python {

void DefineBlasInfo(py::module_& m) {
  py::class_<BlasInfo>(m, "BlasInfo", "The BLAS loaded into this process (docs/blas.md).")
      .def_readonly("library", &BlasInfo::library, "\"OpenBLAS\", \"Intel MKL\", \"BLIS\", ...")
      .def_readonly("config", &BlasInfo::config, "The library's own configuration string.")
      .def_readonly("core_name", &BlasInfo::coreName,
                    "Kernel set in use (\"SkylakeX\", \"Haswell\", ...).")
      .def_readonly("num_threads", &BlasInfo::numThreads, "Threads the BLAS will use.")
      .def_readonly("cpu_has_avx512", &BlasInfo::cpuHasAvx512, "The CPU has AVX-512 F/BW/DQ/VL/CD.")
      .def_readonly("fast_kernels", &BlasInfo::fastKernels,
                    "False when the kernels are of an older tier than the CPU supports.")
      .def_readonly("advice", &BlasInfo::advice, "What to do when fast_kernels is False.")
      .def("__repr__", [](BlasInfo const& b) {
        return "BlasInfo(library='" + b.library + "', core_name='" + b.coreName +
               "', num_threads=" + std::to_string(b.numThreads) +
               ", fast_kernels=" + (b.fastKernels ? "True" : "False") + ")";
      });
  m.def("get_blas_info", &GetBlasInfo, "Inspects the BLAS loaded into this process. Never fails.");
}

}  // namespace superdex::python

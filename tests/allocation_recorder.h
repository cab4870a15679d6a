// Records every heap allocation of the process while a call runs, by
// interposing malloc, calloc, realloc, the aligned allocators and the global
// operator new (all forwarding to glibc's allocator), with the address of
// each caller, so that an allocation can be attributed to SuperDex's own code
// (libsuperdex, with the Eigen and standard-library code inlined into it) or
// to a library it calls (CHOLMOD, libgomp, OpenBLAS).
//
// Link tests/allocation_recorder.cc into the test executable that uses it
// (superdex_add_test(name test.cpp ${PROJECT_SOURCE_DIR}/tests/allocation_recorder.cc));
// the interposition then touches no other test.
#pragma once

#include <functional>

namespace superdex::test {

struct Allocations {
  int total = 0;     ///< every allocation in the process during the call
  int superdex = 0;  ///< those made by code in libsuperdex itself
};

/// Heap allocations made while `call` runs.
Allocations CountAllocations(std::function<void()> const& call);

}  // namespace superdex::test

// Factorize and Solve must not allocate (style habit 3). This executable
// records every heap allocation of the process by interposing malloc, calloc,
// realloc, the aligned allocators and the global operator new (all
// forwarding to glibc's allocator), with the address of the caller, so an
// allocation can be attributed to SuperDex's own code (libsuperdex, Eigen
// inlined into it) or to a library it calls (CHOLMOD, libgomp, OpenBLAS).
// It is a separate executable so that the interposition touches no other test.
#include <dlfcn.h>

#include <atomic>
#include <cerrno>
#include <cstddef>
#include <memory>
#include <new>

#include <catch2/catch.hpp>

#include <superdex/linsolve/cholmod_solver.h>
#include <superdex/linsolve/dense_solver.h>
#include <superdex/linsolve/linear_solver.h>

#include "linsolve/test_systems.h"

extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t count, std::size_t size);
void* __libc_realloc(void* pointer, std::size_t size);
void* __libc_memalign(std::size_t alignment, std::size_t size);
void __libc_free(void* pointer);
}

namespace {

constexpr int kMaxRecorded = 1 << 14;
std::atomic<bool> gRecording{false};
std::atomic<int> gNumAllocations{0};
void* gCallers[kMaxRecorded];

// Called by every interposed allocator with the address it returns to.
void Record(void* caller) {
  if (!gRecording.load(std::memory_order_relaxed)) return;
  int const index = gNumAllocations.fetch_add(1);
  if (index < kMaxRecorded) gCallers[index] = caller;
}

}  // namespace

extern "C" {
void* malloc(std::size_t size) {
  Record(__builtin_return_address(0));
  return __libc_malloc(size);
}
void* calloc(std::size_t count, std::size_t size) {
  Record(__builtin_return_address(0));
  return __libc_calloc(count, size);
}
void* realloc(void* pointer, std::size_t size) {
  Record(__builtin_return_address(0));
  return __libc_realloc(pointer, size);
}
void* memalign(std::size_t alignment, std::size_t size) {
  Record(__builtin_return_address(0));
  return __libc_memalign(alignment, size);
}
void* aligned_alloc(std::size_t alignment, std::size_t size) {
  Record(__builtin_return_address(0));
  return __libc_memalign(alignment, size);
}
int posix_memalign(void** pointer, std::size_t alignment, std::size_t size) {
  Record(__builtin_return_address(0));
  void* result = __libc_memalign(alignment, size);
  if (result == nullptr) return ENOMEM;
  *pointer = result;
  return 0;
}
}

void* operator new(std::size_t size) {
  Record(__builtin_return_address(0));
  if (void* pointer = __libc_malloc(size == 0 ? 1 : size)) return pointer;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  Record(__builtin_return_address(0));
  if (void* pointer = __libc_malloc(size == 0 ? 1 : size)) return pointer;
  throw std::bad_alloc();
}
void operator delete(void* pointer) noexcept {
  __libc_free(pointer);
}
void operator delete[](void* pointer) noexcept {
  __libc_free(pointer);
}
void operator delete(void* pointer, std::size_t) noexcept {
  __libc_free(pointer);
}
void operator delete[](void* pointer, std::size_t) noexcept {
  __libc_free(pointer);
}

namespace superdex {
namespace {

struct Allocations {
  int total = 0;     ///< every allocation in the process during the call
  int superdex = 0;  ///< those made by code in libsuperdex itself
};

/// Heap allocations made while `call` runs.
template <class Call>
Allocations CountAllocations(Call&& call) {
  gNumAllocations = 0;
  gRecording = true;
  call();
  gRecording = false;

  Allocations counts;
  counts.total = gNumAllocations.load();
  REQUIRE(counts.total <= kMaxRecorded);
  Dl_info library;
  REQUIRE(dladdr(reinterpret_cast<void*>(&AvailableLinearSolvers), &library) != 0);
  for (int i = 0; i < counts.total; ++i) {
    Dl_info info;
    if (dladdr(gCallers[i], &info) != 0 && info.dli_fbase == library.dli_fbase) {
      ++counts.superdex;
    }
  }
  return counts;
}

TEST_CASE("the allocation counter sees and attributes allocations", "[linsolve][allocation]") {
  // guards the tests below against an interposition that silently counts
  // nothing: a call into libsuperdex that allocates a vector and a string
  Allocations const counts = CountAllocations([] {
    DynamicArray<LinearSolverType> const types = AvailableLinearSolvers();
    REQUIRE(!types.empty());
    Error error;
    auto solver = CreateLinearSolver(LinearSolverType::Auto, error);
    REQUIRE(error);
  });
  CAPTURE(counts.total, counts.superdex);
  REQUIRE(counts.superdex >= 2);
  REQUIRE(counts.total >= counts.superdex);
}

TEST_CASE("Factorize and Solve do not allocate", "[linsolve][allocation]") {
  // a system below the dense threshold and one above it
  int const size = GENERATE(30, 120);
  CAPTURE(size);
  SparseSymmetricMatrix const a = test::RandomBlockSpd(size / 6, 6, 0.3, 5);
  REQUIRE(a.size == size);
  VectorX const b = test::TestRhs(a.size);
  VectorX x(a.size);
  Span<real const> const bView = test::View(b);
  Span<real> const xView = test::View(x);

  SECTION("dense: nothing at all") {
    internal::DenseCholeskySolver solver;
    REQUIRE(solver.Analyze(a).Ok());
    REQUIRE(solver.Factorize(a).Ok());
    REQUIRE(solver.Solve(bView, xView).Ok());
    LinearSolveResult factorized, solved;
    Allocations const factorize = CountAllocations([&] { factorized = solver.Factorize(a); });
    Allocations const solve = CountAllocations([&] { solved = solver.Solve(bView, xView); });
    REQUIRE(factorized.Ok());
    REQUIRE(solved.Ok());
    CHECK(factorize.total == 0);
    CHECK(solve.total == 0);
  }
  SECTION("CHOLMOD: nothing from SuperDex, nothing in Solve after the first") {
    internal::CholmodSolver solver;
    REQUIRE(solver.Analyze(a).Ok());
    REQUIRE(solver.Factorize(a).Ok());
    LinearSolveResult factorized, solved;
    // the first Solve after Analyze allocates CHOLMOD's solve workspaces
    Allocations const firstSolve = CountAllocations([&] { solved = solver.Solve(bView, xView); });
    REQUIRE(solved.Ok());
    REQUIRE(firstSolve.total > 0);
    Allocations const solve = CountAllocations([&] { solved = solver.Solve(bView, xView); });
    REQUIRE(solved.Ok());
    CHECK(solve.total == 0);

    Allocations const factorize = CountAllocations([&] { factorized = solver.Factorize(a); });
    REQUIRE(factorized.Ok());
    CHECK(factorize.superdex == 0);
    // cholmod_factorize allocates itself: the transpose of the upper triangle,
    // the supernode update matrix, libgomp's team for each (serialised)
    // OpenMP region per supernode, OpenBLAS's threaded SYRK job arrays
    WARN("cholmod_factorize: " << factorize.total << " heap allocations per call, n = " << size
                               << ", " << solver.GetDescription());
  }
}

}  // namespace
}  // namespace superdex

#include "allocation_recorder.h"

#include <cstdio>
#include <cstdlib>

#include <dlfcn.h>

#include <atomic>
#include <cerrno>
#include <cstddef>
#include <new>

#include <catch2/catch.hpp>

#include <superdex/linsolve/linear_solver.h>

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

// called by every interposed allocator with the address it returns to
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
void operator delete(void* pointer) noexcept { __libc_free(pointer); }
void operator delete[](void* pointer) noexcept { __libc_free(pointer); }
void operator delete(void* pointer, std::size_t) noexcept { __libc_free(pointer); }
void operator delete[](void* pointer, std::size_t) noexcept { __libc_free(pointer); }

namespace superdex::test {

Allocations CountAllocations(std::function<void()> const& call) {
  gNumAllocations = 0;
  gRecording = true;
  call();
  gRecording = false;

  Allocations counts;
  counts.total = gNumAllocations.load();
  REQUIRE(counts.total <= kMaxRecorded);
  Dl_info library;
  REQUIRE(dladdr(reinterpret_cast<void*>(&AvailableLinearSolvers), &library) != 0);
  // SUPERDEX_ALLOCATION_TRACE=1 prints where SuperDex's own allocations
  // come from (the nearest exported symbol and the offset into it)
  bool const trace = std::getenv("SUPERDEX_ALLOCATION_TRACE") != nullptr;
  for (int i = 0; i < counts.total; ++i) {
    Dl_info info;
    if (dladdr(gCallers[i], &info) != 0 && info.dli_fbase == library.dli_fbase) {
      ++counts.superdex;
      if (trace)
        std::fprintf(stderr, "allocation from %s+0x%lx\n", info.dli_sname ? info.dli_sname : "?",
                     static_cast<unsigned long>(static_cast<char*>(gCallers[i]) -
                                                static_cast<char*>(info.dli_saddr)));
    }
  }
  return counts;
}

}  // namespace superdex::test

// ParallelExecutor: the threads SuperDex runs its parallel loops on (a oneTBB
// task arena of a fixed size).
//
// Loops run over index ranges; the body gets [begin, end) and the index of
// the thread running it, in [0, GetNumThreads()), for per-thread scratch.
// Results must not depend on how the range is split: the assembler stages
// every contributor's block in its own slots and sums them in a fixed order
// (assembly/hessian_assembler.h), so assembly is bit-identical for any
// thread count.
//
// The thread count follows the machine by default (the CPUs this process may
// run on, sched_getaffinity) and can be set; one thread runs every body
// serially, in order, on the calling thread. TBB stays out of this header.
#pragma once

#include <memory>
#include <type_traits>

namespace superdex::internal {

/// The CPUs this process may run on (its affinity mask), at least 1.
int AvailableCpus();

class ParallelExecutor {
 public:
  ParallelExecutor();
  ~ParallelExecutor();
  ParallelExecutor(ParallelExecutor const&) = delete;
  ParallelExecutor& operator=(ParallelExecutor const&) = delete;

  /// 0: AvailableCpus(); otherwise numThreads (>= 1, the caller checks).
  void SetNumThreads(int numThreads);
  int GetNumThreads() const { return numThreads_; }

  using RangeBody = void (*)(void* context, int begin, int end, int thread);
  /// Runs body over [0, count) in chunks of at least `grain` indices; with
  /// one thread (or count <= grain) as one serial call body(0, count, 0).
  void For(int count, int grain, RangeBody body, void* context) const;

  /// As above with any callable f(begin, end, thread).
  template <class F>
  void For(int count, int grain, F&& f) const {
    using Body = std::remove_reference_t<F>;
    For(count, grain,
        [](void* context, int begin, int end, int thread) { (*static_cast<Body*>(context))(begin, end, thread); },
        const_cast<std::remove_const_t<Body>*>(&f));
  }

 private:
  struct Arena;  // the tbb::task_arena (parallel.cc)
  int numThreads_ = 1;
  std::unique_ptr<Arena> arena_;
};

}  // namespace superdex::internal

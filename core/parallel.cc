#include <superdex/core/parallel.h>

#include <sched.h>

#include <algorithm>

#include <optional>

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace superdex::internal {

int AvailableCpus() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) == 0) return std::max(1, CPU_COUNT(&set));
  return 1;
}

struct ParallelExecutor::Arena {
  explicit Arena(int threads) : arena(threads) {
    // more threads than TBB's default (the CPUs of the affinity mask) were
    // asked for: raise TBB's process-wide worker limit while this arena lives
    if (threads > tbb::info::default_concurrency())
      limit.emplace(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  }
  std::optional<tbb::global_control> limit;
  tbb::task_arena arena;
};

ParallelExecutor::ParallelExecutor() = default;
ParallelExecutor::~ParallelExecutor() = default;

void ParallelExecutor::SetNumThreads(int numThreads) {
  int const threads = numThreads > 0 ? numThreads : AvailableCpus();
  if (threads == numThreads_ && (threads == 1 || arena_)) return;
  numThreads_ = threads;
  arena_ = threads > 1 ? std::make_unique<Arena>(threads) : nullptr;
}

void ParallelExecutor::For(int count, int grain, RangeBody body, void* context) const {
  if (count <= 0) return;
  grain = std::max(grain, 1);
  if (numThreads_ == 1 || !arena_ || count <= grain) {
    body(context, 0, count, 0);
    return;
  }
  arena_->arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, count, grain), [&](tbb::blocked_range<int> const& range) {
      int const thread = std::max(0, tbb::this_task_arena::current_thread_index());
      body(context, range.begin(), range.end(), thread);
    });
  });
}

}  // namespace superdex::internal

#include "core/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace mesocap {

int EffectiveThreadCount(int num_threads) {
  const int cores = tbb::info::default_concurrency();
  return num_threads <= 0 ? cores : num_threads;
}

void ParallelFor(int begin, int end, const std::function<void(int)>& fn, int num_threads) {
  if (end <= begin) return;
  const int threads = EffectiveThreadCount(num_threads);
  if (threads == 1) {
    for (int i = begin; i < end; ++i) fn(i);
    return;
  }
  tbb::task_arena arena(threads);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(begin, end, 1), [&](const tbb::blocked_range<int>& r) {
      for (int i = r.begin(); i != r.end(); ++i) fn(i);
    });
  });
}

}  // namespace mesocap

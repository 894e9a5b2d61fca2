#include "core/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <opencv2/core/utility.hpp>

namespace mesocap {

#if defined(__SANITIZE_THREAD__)
// Under ThreadSanitizer, OpenCV runs its own loops serially. Its cv::parallel_for_ drives oneTBB
// through TBB header code compiled into the uninstrumented libopencv_core, so TSan misses the
// workers' "done" hand-off and reports races on the stack the caller reuses afterwards, in our
// code and in TBB (seen in texton analysis, whose filters call OpenCV inside ParallelFor).
[[maybe_unused]] static const bool kOpenCvSerialUnderTsan = (cv::setNumThreads(1), true);
#endif

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

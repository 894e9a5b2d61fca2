// One way to run work on all cores: TBB, parallelism at one level only.
// num_threads = -1 means all cores; results must never depend on the thread count.
#pragma once

#include <functional>

namespace mesocap {

// Calls fn(i) for i in [begin, end), spread over `num_threads` threads.
void ParallelFor(int begin, int end, const std::function<void(int)>& fn, int num_threads = -1);

int EffectiveThreadCount(int num_threads);

}  // namespace mesocap

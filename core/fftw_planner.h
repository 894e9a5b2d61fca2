// The one lock around FFTW's planner: planning (and destroying a plan) is not thread-safe, while
// executing a plan with the new-array functions is. Every FFT user in mesocap (the steerable
// pyramid, the texton filter bank, FFT patch matching) plans under it, so planning in one stage
// cannot race planning in another that runs on other threads.
#pragma once

#include <mutex>

namespace mesocap {

std::mutex& FftwPlannerMutex();

}  // namespace mesocap

#include "core/fftw_planner.h"

namespace mesocap {

// Defined out of line: one mutex for the whole process, whichever library plans.
std::mutex& FftwPlannerMutex() {
  static std::mutex mutex;
  return mutex;
}

}  // namespace mesocap

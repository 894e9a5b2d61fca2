#include "core/resource_usage.h"

#include <sys/resource.h>

#include <ctime>

namespace mesocap {

double ProcessCpuSeconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

double PeakMemoryMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;
}

}  // namespace mesocap

#include "core/progress.h"

#include <gtest/gtest.h>

#include <atomic>

#include "core/parallel.h"

namespace mesocap {
namespace {

// Workers report as they finish, out of order and at once; under ThreadSanitizer (scripts/
// sanitize.sh thread) this is the regression test for the bar's data race.
TEST(ProgressBar, ParallelWorkersMayReportAtOnce) {
  ProgressBar bar("test", true);
  const ProgressFn report = bar.AsCallback();
  std::atomic<int> done{0};
  std::atomic<int> refused{0};
  ParallelFor(0, 20000, [&](int i) {
    if (!report(++done, 20000, "item " + std::to_string(i))) ++refused;
  });
  EXPECT_EQ(refused, 0);
  EXPECT_TRUE(bar.Update(20000, 20000, "end"));
}

}  // namespace
}  // namespace mesocap

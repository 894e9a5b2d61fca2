// Ctrl-C through the real CLI (core/cancel.h): SIGINT at a moment drawn after start-up stops a
// long command with exit code 3, leaves no staging folder or temp file beside its output, and the
// same command run again completes. The wait after SIGINT is bounded generously (a hang guard,
// not a timing assertion: tests share 2 cores); each run prints its latency
// (`ctest -R e2e/cancel -V`).
#include <gtest/gtest.h>

#include <filesystem>

#include "core/image_io.h"
#include "tests/e2e/interrupt.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

namespace fs = std::filesystem;

fs::path Photograph(const std::string& name) {
  return fs::path(MESOCAP_SOURCE_DIR) / "tests" / "data" / "textures" / (name + ".png");
}

TEST(Cancel, SynthStopsCleanlyAndRunsAgain) {
  const fs::path work = testing::MakeTempDir();
  // Texton synthesis of 512 x 512 from a 128 x 128 photograph: about 6 s on 2 idle cores.
  ExpectCancelledCleanlyThenCompletes("synth --method texton --input " + Photograph("bark").string() +
                                          " --size 512 --no-progress --out " + (work / "bark").string(),
                                      work, DrawDelay(0.5, 3.0));
  EXPECT_TRUE(fs::exists(work / "bark" / "map.exr"));
}

TEST(Cancel, PaintStopsCleanlyAndRunsAgain) {
  const fs::path work = testing::MakeTempDir();
  Image feature(128, 128, 1, 0.f), target(512, 512, 1, 0.f);
  for (int y = 40; y < 80; ++y)
    for (int x = 40; x < 80; ++x) feature.at(x, y) = 1;
  for (int y = 0; y < 512; ++y)
    for (int x = 0; x < 512; ++x) target.at(x, y) = std::hypot(x - 256.0, y - 256.0) < 60;
  ASSERT_TRUE(WriteImage(work / "feature.png", feature, {.format = PixelFormat::kUint8Srgb}).ok());
  ASSERT_TRUE(WriteImage(work / "target.png", target, {.format = PixelFormat::kUint8Srgb}).ok());
  ExpectCancelledCleanlyThenCompletes("paint --input " + Photograph("pebbles").string() + " --feature-mask " +
                                          (work / "feature.png").string() + " --target-mask " +
                                          (work / "target.png").string() + " --size 512 --no-progress --out " +
                                          (work / "painted").string(),
                                      work, DrawDelay(0.3, 1.5));
  EXPECT_TRUE(fs::exists(work / "painted" / "map.exr"));
}

// process on a small rendered session: SIGINT while its stages run; the stage it was in leaves no
// staging folder, stages.json stays whole, and the rerun completes every stage.
TEST(Cancel, ProcessStopsCleanlyAndRunsAgain) {
  const fs::path work = testing::MakeTempDir(), session = work / "session";
  std::string out;
  ASSERT_EQ(testing::RunMesocap("simulate --out " + session.string() +
                                    " --shots 10 --calib-shots 0 --width 1500 --height 1000 --no-progress",
                                &out),
            0)
      << out;
  // Calibrate and resample take about 5 s, the Bonn grid's reconstruction several more.
  ExpectCancelledCleanlyThenCompletes("process " + session.string() + " --camera " + (session / "truth.json").string() +
                                          " --slice-size 32 --btf-size 32 --btf-grid bonn --no-progress",
                                      work, DrawDelay(1.0, 6.0));
  EXPECT_TRUE(fs::exists(session / "btf" / "index.json"));
}

}  // namespace
}  // namespace mesocap

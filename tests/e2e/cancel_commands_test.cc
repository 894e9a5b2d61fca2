// Ctrl-C into every long command but those of cancel_test.cc (synth, paint, process): reconstruct,
// synth-apply, evaluate, import, fit-ptm, calibrate, calibrate-camera and export, each on inputs
// that keep it busy for a few seconds on 2 cores. SIGINT at a moment drawn inside that time: exit
// code 3, nothing half-made left (tests/e2e/interrupt.h), and the same command then completes.
// Each run prints how long after SIGINT it ended (`ctest -R e2e/cancel_commands -V`).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/image_io.h"
#include "core/session_layout.h"
#include "formats/lp_file.h"
#include "tests/e2e/interrupt.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

// One rendered session shared by the tests: 10 shots at 1500x1000, calibrated, with a coarse
// reconstructed BTF at 128 texels (289 slices) in its btf/. Tests that write into it copy it.
class CancelCommands : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    work_ = new fs::path(testing::MakeTempDir());
    session_ = new fs::path(*work_ / "session");
    std::string out;
    ASSERT_EQ(testing::RunMesocap("simulate --out " + session_->string() +
                                      " --shots 10 --calib-shots 0 --width 1500 --height 1000 --no-progress",
                                  &out),
              0)
        << out;
    fs::copy(*session_, *work_ / "uncalibrated", fs::copy_options::recursive);
    ASSERT_EQ(testing::RunMesocap("calibrate " + session_->string() + " --camera " + truth().string() +
                                      " --slice-size 64 --no-progress",
                                  &out),
              0)
        << out;
    ASSERT_EQ(testing::RunMesocap("reconstruct " + session_->string() + " --grid coarse --size 128 --out " +
                                      SessionLayout(*session_).btf().root.string() + " --no-progress",
                                  &out),
              0)
        << out;
  }
  static void TearDownTestSuite() {
    fs::remove_all(*work_);
    delete session_;
    delete work_;
  }
  static fs::path truth() { return SessionLayout(*session_).truth(); }
  // A copy of the shared session in a fresh folder, for a command that writes into it.
  static fs::path CopyOfSession(const fs::path& into) {
    fs::copy(*session_, into, fs::copy_options::recursive);
    return into;
  }

  static fs::path* work_;
  static fs::path* session_;
};
fs::path* CancelCommands::work_ = nullptr;
fs::path* CancelCommands::session_ = nullptr;

Eigen::Vector3d Direction(double elevation_deg, double azimuth_deg) {
  const double e = elevation_deg * std::numbers::pi / 180, a = azimuth_deg * std::numbers::pi / 180;
  return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

// A photograph-like 3000x2000 JPEG (a smooth pattern with fine texture).
void WritePhoto(const fs::path& path) {
  Image photo(3000, 2000, 3);
  for (int y = 0; y < photo.height(); ++y)
    for (int x = 0; x < photo.width(); ++x)
      for (int c = 0; c < 3; ++c)
        photo.at(x, y, c) = float(0.3 + 0.2 * std::sin(0.01 * x + 0.7 * c) * std::cos(0.013 * y) + 0.05 * ((x * 7 + y * 13) % 11) / 11.0);
  ASSERT_TRUE(WriteImage(path, photo).ok());
}

TEST_F(CancelCommands, ReconstructStopsCleanlyAndRunsAgain) {
  const fs::path work = testing::MakeTempDir();
  // The Bonn grid's 6561 slices at 32 texels: several seconds.
  ExpectCancelledCleanlyThenCompletes("reconstruct " + session_->string() + " --grid bonn --size 32 --no-progress --out " +
                                          (work / "btf").string(),
                                      work, DrawDelay(0.5, 2.0));
  EXPECT_TRUE(fs::exists(BtfFolder{work / "btf"}.index()));
}

TEST_F(CancelCommands, SynthApplyStopsCleanlyAndRunsAgain) {
  const fs::path work = testing::MakeTempDir();
  std::string out;
  // A map into a 128x128 sample (the BTF's size), found on a photograph of that size.
  const fs::path bark = fs::path(MESOCAP_SOURCE_DIR) / "tests" / "data" / "textures" / "bark.png";
  ASSERT_EQ(testing::RunMesocap("synth --method quilt --input " + bark.string() + " --size 384 --no-progress --out " +
                                    (work / "map").string(),
                                &out),
            0)
      << out;
  // 289 slices enlarged to 384x384.
  ExpectCancelledCleanlyThenCompletes("synth-apply --map " + SynthFolder{work / "map"}.map().string() + " --input " +
                                          SessionLayout(*session_).btf().root.string() + " --no-progress --out " +
                                          (work / "applied").string(),
                                      work, DrawDelay(0.5, 2.0));
  EXPECT_TRUE(fs::exists(SynthFolder{work / "applied"}.report()));
}

TEST_F(CancelCommands, EvaluateStopsCleanlyAndRunsAgain) {
  const fs::path work = testing::MakeTempDir();
  ExpectCancelledCleanlyThenCompletes("evaluate --material weave --size 64 --pairs 400 --no-progress --out " +
                                          (work / "eval").string(),
                                      work, DrawDelay(0.5, 2.5));
  EXPECT_TRUE(fs::exists(work / "eval" / "evaluation.json"));
}

TEST_F(CancelCommands, ImportStopsCleanlyAndRunsAgain) {
  const fs::path work = testing::MakeTempDir(), photos = work / "photos";
  fs::create_directories(photos);
  WritePhoto(photos / "p000.jpg");
  // The same bytes under 40 names: each is still decoded (capture time, size) and copied.
  for (int k = 1; k < 40; ++k) fs::copy_file(photos / "p000.jpg", photos / ("p" + std::to_string(1000 + k).substr(1) + ".jpg"));
  ExpectCancelledCleanlyThenCompletes("import " + photos.string() + " --link copy --no-progress --out " +
                                          (work / "imported").string(),
                                      work, DrawDelay(0.3, 2.0));
  EXPECT_TRUE(fs::exists(SessionLayout(work / "imported").manifest()));
}

TEST_F(CancelCommands, FitPtmStopsCleanlyAndRunsAgain) {
  const fs::path work = testing::MakeTempDir();
  WritePhoto(work / "img_0.jpg");
  std::vector<LpEntry> entries;
  for (int k = 0; k < 96; ++k) {
    const fs::path image = work / ("img_" + std::to_string(k) + ".jpg");
    if (k > 0) fs::create_hard_link(work / "img_0.jpg", image);
    entries.push_back({image, Direction(30 + 50.0 * (k % 4) / 4, 360.0 * k / 96)});
  }
  ASSERT_TRUE(WriteLpFile(work / "capture.lp", entries).ok());
  ExpectCancelledCleanlyThenCompletes("fit-ptm --lp " + (work / "capture.lp").string() + " --out " +
                                          (work / "out.ptm").string() + " --no-progress",
                                      work, DrawDelay(0.3, 1.2));
  EXPECT_TRUE(fs::exists(work / "out.ptm"));
}

TEST_F(CancelCommands, CalibrateStopsCleanlyAndRunsAgain) {
  const fs::path work = testing::MakeTempDir();
  fs::copy(*work_ / "uncalibrated", work / "session", fs::copy_options::recursive);
  const SessionLayout session(work / "session");
  // Early: inside the calibration proper (balls, tags, flash per shot), before resampling.
  ExpectCancelledCleanlyThenCompletes("calibrate " + session.root().string() + " --camera " +
                                          session.truth().string() + " --slice-size 64 --no-progress",
                                      work, DrawDelay(0.3, 1.5));
  EXPECT_TRUE(fs::exists(session.slices().index()));
}

TEST_F(CancelCommands, CalibrateCameraStopsCleanlyAndRunsAgain) {
  const fs::path work = testing::MakeTempDir(), boards = work / "boards";
  fs::create_directories(boards);
  const fs::path photos = fs::path(MESOCAP_SOURCE_DIR) / "tests" / "data" / "opencv_chessboard";
  for (int copy = 0; copy < 2; ++copy)
    for (const auto& e : fs::directory_iterator(photos))
      if (e.path().extension() == ".jpg")
        fs::copy_file(e.path(), boards / (std::to_string(copy) + "_" + e.path().filename().string()));
  // The accurate detector on 52 photos: a few seconds.
  ExpectCancelledCleanlyThenCompletes("calibrate-camera --images " + boards.string() +
                                          " --board 9x6 --square 0.025 --refinement sb-accuracy --no-progress --out " +
                                          (work / "camera.json").string(),
                                      work, DrawDelay(0.3, 1.5));
  EXPECT_TRUE(fs::exists(work / "camera.json"));
}

TEST_F(CancelCommands, ExportStopsCleanlyAndRunsAgain) {
  const fs::path work = testing::MakeTempDir();
  const SessionLayout session(CopyOfSession(work / "session"));
  // The glTF material fitted per texel to the 128x128 BTF: a few seconds.
  ExpectCancelledCleanlyThenCompletes("export " + session.root().string() + " --format gltf", work, DrawDelay(0.3, 2.0));
  EXPECT_TRUE(fs::exists(session.exports().gltf().material()));
}

}  // namespace
}  // namespace mesocap

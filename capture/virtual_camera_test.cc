// The virtual rig as a camera: a capture run through it gives the bytes `mesocap simulate`
// writes for the same options, so tethered and virtual sessions are interchangeable.
#include "capture/virtual_camera.h"

#include <gtest/gtest.h>

#include "capture/simulate.h"
#include "capture/tethered_capture.h"
#include "core/atomic_file.h"
#include "core/session.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

TEST(VirtualCamera, CaptureRunMatchesSimulateByteForByte) {
  const auto dir = testing::MakeTempDir();
  SimulateOptions sim;
  sim.rig.seed = 5;
  sim.rig.width = 900;
  sim.rig.height = 600;
  sim.rig.shots = 3;
  sim.rig.calib_shots = 2;
  sim.out = dir / "simulated";
  ASSERT_TRUE(SimulateSession(sim).ok());

  auto camera = CreateCamera("virtual", "virtual:seed=5,width=900,height=600,shots=3,calib-shots=2");
  ASSERT_TRUE(camera.ok()) << camera.status().message();
  CaptureOptions calib;
  calib.out = dir / "captured";
  calib.shots = 2;
  calib.calibration = true;
  calib.settings = {"subject=checkerboard"};
  auto first = RunCapture(**camera, calib);
  ASSERT_TRUE(first.ok()) << first.status().message();
  CaptureOptions flash;
  flash.out = dir / "captured";
  flash.shots = 3;
  flash.resume = true;
  flash.settings = {"subject=flash"};
  auto second = RunCapture(**camera, flash);
  ASSERT_TRUE(second.ok()) << second.status().message();

  auto session = Session::Open(dir / "captured");
  ASSERT_TRUE(session.ok());
  ASSERT_EQ(session->ShotsOfKind("shot").size(), 3u);
  ASSERT_EQ(session->ShotsOfKind("calib").size(), 2u);
  for (const auto& r : session->shots()) {
    const std::string name = std::filesystem::path(r.file).filename().string();
    const std::string sub = r.kind == "calib" ? "calib" : "shots";
    EXPECT_EQ(*ReadTextFile(dir / "captured" / r.file), *ReadTextFile(dir / "simulated" / sub / name)) << r.file;
  }
  // The rig has no fourth flash shot: the card is "full", the three shots stay.
  CaptureOptions more = flash;
  more.shots = 1;
  auto third = RunCapture(**camera, more);
  EXPECT_FALSE(third.ok() && third->shots_captured > 0);
  EXPECT_EQ(Session::Open(dir / "captured")->ShotsOfKind("shot").size(), 3u);
}

TEST(VirtualCamera, BadPortAndSettingsAreExplained) {
  auto bad = CreateCamera("virtual", "virtual:colour=red");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("unknown key 'colour'"), std::string::npos);
  auto camera = CreateCamera("virtual", "virtual:width=900,height=600,shots=1,calib-shots=0");
  ASSERT_TRUE(camera.ok());
  const CameraStatus st = (*camera)->SetConfig("subject", "moon");
  EXPECT_EQ(st.error, CameraError::kBadSetting);
  EXPECT_NE(st.message.find("checkerboard"), std::string::npos);
}

// The photographer can be told where to hold the flash; hand-held shots carry on where they
// left off.
TEST(VirtualCamera, TakesFlashShotsWhereAsked) {
  auto opened = VirtualCamera::Open("virtual:seed=6,width=640,height=400,shots=3,calib-shots=0");
  ASSERT_TRUE(opened.ok()) << opened.status().message();
  VirtualCamera& camera = **opened;
  CameraFilePath on_card;
  ASSERT_TRUE(camera.Capture(&on_card).ok());
  ASSERT_TRUE(camera.SetConfig("flashposition", "0.4,-0.2,0.3").ok());
  ASSERT_TRUE(camera.Capture(&on_card).ok());
  EXPECT_EQ(on_card.name, "shot_0002.jpg");
  ASSERT_TRUE(camera.SetConfig("flashposition", "hand-held").ok());
  ASSERT_TRUE(camera.Capture(&on_card).ok());
  const std::vector<RigShot>& taken = camera.flash_shots_taken();
  ASSERT_EQ(taken.size(), 3u);
  EXPECT_EQ(taken[0].light_m, camera.scene().shots[0].light_m);
  EXPECT_EQ(taken[1].light_m, Eigen::Vector3d(0.4, -0.2, 0.3));
  EXPECT_NEAR(taken[1].power, 1.0, 0.15);
  EXPECT_EQ(taken[2].light_m, camera.scene().shots[1].light_m);
  for (const char* bad : {"0.4,-0.2", "0.4,-0.2,0.3,1", "a,b,c", "0.4,nan,0.3", "near"}) {
    const CameraStatus st = camera.SetConfig("flashposition", bad);
    EXPECT_EQ(st.error, CameraError::kBadSetting) << bad;
    EXPECT_NE(st.message.find("hand-held"), std::string::npos) << st.message;
  }
}

// A person following the guide misses the asked position by about follow-error metres per axis:
// the spread of many shots' offsets matches it, and none lands exactly where asked.
TEST(VirtualCamera, APersonFollowingTheGuideMissesByTheGivenError) {
  auto opened = VirtualCamera::Open("virtual:seed=8,width=640,height=400,shots=1,calib-shots=0,follow-error=0.05");
  ASSERT_TRUE(opened.ok()) << opened.status().message();
  VirtualCamera& camera = **opened;
  const Eigen::Vector3d asked(0.4, -0.2, 0.3);
  ASSERT_TRUE(camera.SetConfig("flashposition", FlashPositionValue(asked)).ok());
  CameraFilePath on_card;
  const int shots = 20;
  for (int i = 0; i < shots; ++i) ASSERT_TRUE(camera.Capture(&on_card).ok());
  double sum_sq = 0;
  for (const RigShot& shot : camera.flash_shots_taken()) {
    const Eigen::Vector3d miss = shot.light_m - asked;
    EXPECT_GT(miss.norm(), 0);
    sum_sq += miss.squaredNorm();
  }
  const double sigma = std::sqrt(sum_sq / (3.0 * shots));  // 60 samples: within 24% of 0.05 at 2.6 sigma
  EXPECT_NEAR(sigma, 0.05, 0.012);
  for (const char* bad : {"follow-error=-1", "follow-error=2", "follow-error=x"})
    EXPECT_FALSE(VirtualCamera::Open(std::string("virtual:") + bad).ok()) << bad;
}

}  // namespace
}  // namespace mesocap

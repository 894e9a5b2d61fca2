// The real libgphoto2 path against libgphoto2's virtual USB camera (a Nikon D750 over PTP),
// built by scripts/build-vusb.sh. If it cannot be built this test FAILS (set MESOCAP_NO_VUSB=1
// to skip it deliberately). The virtual camera reports its card full after 26 captures on one
// connection (its port library, and the capture counter in it, is reloaded on every open), so
// each test opens its own connection.
#include "capture/gphoto2_camera.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <set>

#include "capture/tethered_capture.h"
#include "core/atomic_file.h"
#include "core/session.h"
#include "tests/testing.h"

namespace mesocap {
namespace {
namespace fs = std::filesystem;

// The source tree, from the build (not __FILE__: ccache's base_dir makes that relative).
const fs::path kRepo = MESOCAP_SOURCE_DIR;

struct Vusb {
  bool skipped = false;
  std::string error;   // why it could not be built
  fs::path iolibs;     // folder holding only vusb.so
  fs::path served;     // the JPEG every capture duplicates
};

// Builds (or finds in its cache) the virtual camera once per process and points IOLIBS at it.
const Vusb& GetVusb() {
  static const Vusb vusb = [] {
    Vusb v;
    if (const char* no = std::getenv("MESOCAP_NO_VUSB"); no && std::string(no) == "1") {
      v.skipped = true;
      return v;
    }
    const char* cache_env = std::getenv("MESOCAP_VUSB_CACHE");
    const fs::path cache = cache_env ? fs::path(cache_env) : kRepo / "build" / "vusb";
    const std::string cmd = "bash '" + (kRepo / "scripts" / "build-vusb.sh").string() + "' '" + cache.string() + "' 2>&1";
    FILE* pipe = ::popen(cmd.c_str(), "r");
    std::string out;
    if (pipe) {
      char buf[4096];
      size_t n;
      while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) out.append(buf, n);
    }
    const int status = pipe ? ::pclose(pipe) : -1;
    if (status != 0) {
      const int rc = status > 0 && WIFEXITED(status) ? WEXITSTATUS(status) : status;
      v.error = "scripts/build-vusb.sh failed (exit " + std::to_string(rc) + "):\n" + out +
                "\nset MESOCAP_NO_VUSB=1 to skip the virtual-camera tests deliberately";
      return v;
    }
    v.iolibs = cache / "iolibs";
    v.served = cache / "vcamera" / "DCIM" / "100TEST" / "DSC_0001.jpg";
    if (!fs::exists(v.iolibs / "vusb.so") || !fs::exists(v.served)) {
      v.error = "scripts/build-vusb.sh succeeded but left no " + (v.iolibs / "vusb.so").string() + " or " +
                v.served.string() + ":\n" + out;
      return v;
    }
    ::setenv("IOLIBS", v.iolibs.c_str(), 1);  // before libgphoto2 loads its port drivers
    return v;
  }();
  return vusb;
}

#define REQUIRE_VUSB()                                                        \
  do {                                                                        \
    const Vusb& v = GetVusb();                                                \
    if (v.skipped) GTEST_SKIP() << "MESOCAP_NO_VUSB=1: virtual camera tests skipped"; \
    ASSERT_TRUE(v.error.empty()) << v.error;                                  \
  } while (0)

std::unique_ptr<Camera> OpenVusb() {
  auto camera = CreateCamera();
  EXPECT_TRUE(camera.ok()) << camera.status().message();
  return camera.ok() ? std::move(*camera) : nullptr;
}

TEST(Gphoto2Camera, DetectsTheVirtualD750) {
  REQUIRE_VUSB();
  auto cameras = ListCameras();
  ASSERT_TRUE(cameras.ok()) << cameras.status().message();
  ASSERT_EQ(cameras->size(), 1u);
  EXPECT_NE((*cameras)[0].model.find("D750"), std::string::npos) << (*cameras)[0].model;
  EXPECT_EQ((*cameras)[0].port.rfind("usb:", 0), 0u) << (*cameras)[0].port;

  // By model and port explicitly (abilities + port info lists), and a wrong model is explained.
  auto by_name = Gphoto2Camera::Open((*cameras)[0].model, (*cameras)[0].port);
  ASSERT_TRUE(by_name.ok()) << by_name.status().message();
  (*by_name)->Close();
  auto wrong = Gphoto2Camera::Open("Canon EOS 5D", "");
  ASSERT_FALSE(wrong.ok());
  EXPECT_NE(wrong.status().message().find("D750"), std::string::npos) << wrong.status().message();
}

TEST(Gphoto2Camera, ConfigSetThroughTheInterfaceReadsBackChanged) {
  REQUIRE_VUSB();
  auto camera = OpenVusb();
  ASSERT_TRUE(camera);
  std::vector<ConfigEntry> entries;
  ASSERT_TRUE(camera->ListConfig(&entries).ok());
  std::set<std::string> names;
  for (const auto& e : entries) names.insert(e.name);
  for (const char* key : {"f-number", "shutterspeed", "exposurecompensation", "imagesize", "capturetarget"})
    EXPECT_TRUE(names.count(key)) << key << " missing from the D750 configuration";

  for (const char* key : {"f-number", "shutterspeed", "exposurecompensation"}) {
    SCOPED_TRACE(key);
    ConfigEntry before;
    ASSERT_TRUE(camera->GetConfig(key, &before).ok());
    ASSERT_GE(before.choices.size(), 2u) << before.type;
    std::string other;
    for (const auto& c : before.choices)
      if (c != before.value) other = c;
    ASSERT_FALSE(other.empty());
    CameraStatus st = camera->SetConfig(key, other);
    ASSERT_TRUE(st.ok()) << st.message;
    ConfigEntry after;
    ASSERT_TRUE(camera->GetConfig(key, &after).ok());
    EXPECT_EQ(after.value, other) << "was " << before.value;
    // Read back through a fresh configuration tree from the camera. (Not across a reconnection:
    // the virtual camera starts from its defaults each time its port is opened.)
    std::vector<ConfigEntry> all;
    ASSERT_TRUE(camera->ListConfig(&all).ok());
    for (const auto& e : all) {
      if (e.name == key) {
        EXPECT_EQ(e.value, other);
      }
    }
  }

  CameraStatus bad_key = camera->SetConfig("iso", "400");  // the virtual D750 has no ISO
  EXPECT_EQ(bad_key.error, CameraError::kBadSetting);
  EXPECT_NE(bad_key.message.find("settable keys:"), std::string::npos) << bad_key.message;
  EXPECT_NE(bad_key.message.find("f-number"), std::string::npos) << bad_key.message;
  CameraStatus bad_value = camera->SetConfig("f-number", "f/0.1");
  EXPECT_EQ(bad_value.error, CameraError::kBadSetting);
  EXPECT_NE(bad_value.message.find("choices:"), std::string::npos) << bad_value.message;
  EXPECT_EQ(ValidateSettings(*camera, {"f-number=f/0.1"}).error, CameraError::kBadSetting);
}

TEST(Gphoto2Camera, TwentyShotsLandOnceWithTheBytesTheCameraServed) {
  REQUIRE_VUSB();
  const fs::path root = testing::MakeTempDir() / "session";
  auto camera = OpenVusb();
  ASSERT_TRUE(camera);
  ConfigEntry fnumber;
  ASSERT_TRUE(camera->GetConfig("f-number", &fnumber).ok());
  CaptureOptions options;
  options.out = root;
  options.shots = 20;
  options.settings = {"f-number=" + fnumber.choices.front()};
  auto report = RunCapture(*camera, options);
  ASSERT_TRUE(report.ok()) << report.status().message();
  ASSERT_TRUE(report->ok()) << report->error;
  EXPECT_EQ(report->shots_captured, 20);
  std::printf("vusb: %d shots, camera capture+download %.2f ms/shot, mesocap overhead %.2f ms/shot (max %.2f)\n",
              report->shots_captured, report->mean_camera_s * 1e3, report->mean_overhead_s * 1e3,
              report->max_overhead_s * 1e3);
  // Issue 3's 50 ms per shot is measured by bench/capture_overhead.sh, not asserted here: tests run
  // in parallel, and a shot that waits for a busy core says nothing about mesocap.
  EXPECT_GE(report->mean_overhead_s, 0.0);

  auto served = ReadTextFile(GetVusb().served);
  ASSERT_TRUE(served.ok());
  auto session = Session::Open(root);
  ASSERT_TRUE(session.ok()) << session.status().message();
  EXPECT_EQ(session->manifest().value("source", ""), "gphoto2");
  const auto shots = session->ShotsOfKind("shot");
  ASSERT_EQ(shots.size(), 20u);
  std::set<int> indices;
  std::set<std::string> on_card;
  std::set<std::string> files;
  for (const auto& r : shots) {
    EXPECT_TRUE(indices.insert(r.index).second) << r.index;
    EXPECT_TRUE(on_card.insert(r.settings.value("camera_file", "")).second) << "downloaded twice: " << r.file;
    files.insert(fs::path(r.file).filename().string());
    auto bytes = ReadTextFile(root / r.file);
    ASSERT_TRUE(bytes.ok());
    EXPECT_EQ(*bytes, *served) << r.file << " differs from what the camera served";
    EXPECT_EQ(r.settings.value("f-number", ""), fnumber.choices.front());
    EXPECT_NEAR(r.exif.value("FNumber", 0.0), 8.0, 1e-6);  // EXIF read back from the file
    EXPECT_EQ(r.exif.value("Flash", -1), 1);
    EXPECT_TRUE(r.flags.empty());
  }
  EXPECT_EQ(*indices.rbegin(), 20);
  std::set<std::string> present;
  for (const auto& e : fs::directory_iterator(root / "shots")) present.insert(e.path().filename().string());
  EXPECT_EQ(present, files);  // nothing else, no temp file
}

TEST(Gphoto2Camera, RemoteModeDownloadsTriggeredFiles) {
  REQUIRE_VUSB();
  const fs::path root = testing::MakeTempDir() / "session";
  auto camera = OpenVusb();
  ASSERT_TRUE(camera);
  CameraStatus st = camera->TriggerCapture();
  ASSERT_TRUE(st.ok()) << st.message;
  CaptureOptions options;
  options.out = root;
  options.mode = CaptureMode::kRemote;
  options.shots = 1;
  auto report = RunCapture(*camera, options);
  ASSERT_TRUE(report.ok()) << report.status().message();
  ASSERT_TRUE(report->ok()) << report->error;
  ASSERT_EQ(report->shots_captured, 1);
  auto served = ReadTextFile(GetVusb().served);
  auto got = ReadTextFile(root / report->shots[0].file);
  ASSERT_TRUE(served.ok() && got.ok());
  EXPECT_EQ(*got, *served);
}

TEST(Gphoto2Camera, CardFullEndsTheRunWithShotsIntact) {
  REQUIRE_VUSB();
  const fs::path root = testing::MakeTempDir() / "session";
  auto camera = OpenVusb();
  ASSERT_TRUE(camera);
  CaptureOptions options;
  options.out = root;
  options.shots = 30;  // more than the 26 the virtual card holds per connection
  options.retry.initial_backoff_s = 0.01;
  const auto t0 = std::chrono::steady_clock::now();
  auto report = RunCapture(*camera, options);
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_FALSE(report->ok());
  EXPECT_EQ(report->stop_reason, "card_full") << report->error;
  EXPECT_EQ(report->shots_captured, 26);
  EXPECT_NE(report->error.find("--resume"), std::string::npos) << report->error;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 120.0);
  auto session = Session::Open(root);
  ASSERT_TRUE(session.ok());
  EXPECT_EQ(int(session->ShotsOfKind("shot").size()), report->shots_captured);
}

}  // namespace
}  // namespace mesocap

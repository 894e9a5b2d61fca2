// Tethered capture against the fake camera: faults (busy, unplugged, damaged download, full
// disk), settings, resume numbering and recovery, and kill -9 at a random moment.
#include "capture/tethered_capture.h"

#include "core/session_lock.h"

#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <thread>

#include "capture/fake_camera.h"
#include "core/atomic_file.h"
#include "core/image_io.h"
#include "core/json.h"
#include "core/session.h"
#include "tests/testing.h"

namespace mesocap {
namespace {
namespace fs = std::filesystem;

Image TestImage(int k) {
  Image image(48, 32, 3);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      for (int c = 0; c < 3; ++c) image.at(x, y, c) = float((x * (k + 1) + y * (c + 2) + 17 * k) % 64) / 64.0f;
  return image;
}

// Three distinct JPEGs with flash-shot EXIF; the third says the flash did not fire.
std::vector<fs::path> MakePhotos(const fs::path& dir) {
  fs::create_directories(dir);
  std::vector<fs::path> photos;
  for (int k = 0; k < 3; ++k) {
    const fs::path path = dir / ("photo_" + std::to_string(k) + ".jpg");
    ImageWriteOptions o;
    o.attributes["Make"] = std::string("TestCam");
    o.attributes["Model"] = std::string("T1");
    o.attributes["ExposureTime"] = 1.0f / 125;
    o.attributes["FNumber"] = 8.0f;
    o.attributes["Exif:PhotographicSensitivity"] = 200;
    o.attributes["Exif:Flash"] = k == 2 ? 16 : 1;  // 16: flash off, did not fire
    EXPECT_TRUE(WriteImage(path, TestImage(k), o).ok()) << path;
    photos.push_back(path);
  }
  return photos;
}

std::string Bytes(const fs::path& path) {
  auto text = ReadTextFile(path);
  return text.ok() ? *text : "<unreadable " + path.string() + ">";
}

CaptureOptions FastOptions(const fs::path& out, int shots) {
  CaptureOptions o;
  o.out = out;
  o.shots = shots;
  o.retry.initial_backoff_s = 0.001;
  o.retry.max_backoff_s = 0.004;
  return o;
}

// Every file in shots/ (hidden temp files included), by name.
std::vector<std::string> FilesIn(const fs::path& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    names.push_back(it->path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// The session holds exactly `n` shots numbered 1..n, each journaled once, each file present
// with bytes identical to one of `photos`, and nothing else in shots/.
void ExpectIntactSession(const fs::path& root, int n, const std::vector<fs::path>& photos) {
  auto session = Session::Open(root);
  ASSERT_TRUE(session.ok()) << session.status().message();
  const auto shots = session->ShotsOfKind("shot");
  ASSERT_EQ(int(shots.size()), n);
  std::set<std::string> photo_bytes;
  for (const auto& p : photos) photo_bytes.insert(Bytes(p));
  std::set<int> indices;
  std::vector<std::string> expected_files;
  for (const auto& r : shots) {
    EXPECT_TRUE(indices.insert(r.index).second) << "index " << r.index << " journaled twice";
    EXPECT_TRUE(photo_bytes.count(Bytes(root / r.file))) << r.file << " differs from every served photo";
    expected_files.push_back(fs::path(r.file).filename().string());
  }
  EXPECT_EQ(*indices.begin(), 1);
  EXPECT_EQ(*indices.rbegin(), n);
  std::sort(expected_files.begin(), expected_files.end());
  EXPECT_EQ(FilesIn(root / "shots"), expected_files);
}

TEST(TetheredCapture, TwentyShotsLandOnceWithTheCameraBytesAndExif) {
  const fs::path tmp = testing::MakeTempDir();
  FakeCameraOptions fo;
  fo.photos = MakePhotos(tmp / "photos");
  FakeCamera camera(fo);
  auto options = FastOptions(tmp / "session", 20);
  int progress_calls = 0;
  auto report = RunCapture(camera, options, [&](int done, int total, const std::string& what) {
    ++progress_calls;
    EXPECT_EQ(total, 20);
    EXPECT_NE(what.find("shot_"), std::string::npos) << what;
    return true;
  });
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_TRUE(report->ok()) << report->error;
  EXPECT_EQ(report->stop_reason, "done");
  EXPECT_EQ(report->shots_captured, 20);
  EXPECT_EQ(progress_calls, 20);
  EXPECT_EQ(camera.captures(), 20);
  ExpectIntactSession(tmp / "session", 20, fo.photos);

  auto session = Session::Open(tmp / "session");
  ASSERT_TRUE(session.ok());
  EXPECT_EQ(session->manifest().value("source", ""), "fake");
  int not_fired = 0;
  for (const auto& r : session->ShotsOfKind("shot")) {
    // Capture k serves photos[(k - 1) % 3]: bytes identical, the flag only on the third photo.
    const fs::path served = fo.photos[size_t(r.index - 1) % 3];
    EXPECT_EQ(Bytes(tmp / "session" / r.file), Bytes(served)) << r.file;
    EXPECT_NEAR(r.exif.value("ExposureTime", 0.0), 1.0 / 125, 1e-6);
    EXPECT_NEAR(r.exif.value("FNumber", 0.0), 8.0, 1e-6);
    EXPECT_EQ(r.exif.value("ISO", 0), 200);
    EXPECT_EQ(r.settings.value("iso", ""), "200");
    EXPECT_EQ(r.settings.value("f-number", ""), "f/8");
    EXPECT_FALSE(r.time_utc.empty());
    const bool flagged = std::find(r.flags.begin(), r.flags.end(), "flash_not_fired") != r.flags.end();
    EXPECT_EQ(flagged, (r.index - 1) % 3 == 2) << r.file;
    not_fired += flagged;
  }
  EXPECT_EQ(not_fired, 6);
  EXPECT_EQ(report->flash_not_fired, 6);
  EXPECT_TRUE(fs::exists(tmp / "session" / "capture_report.json"));
}

TEST(TetheredCapture, CalibrationShotsGoToCalib) {
  const fs::path tmp = testing::MakeTempDir();
  FakeCameraOptions fo;
  fo.photos = MakePhotos(tmp / "photos");
  FakeCamera camera(fo);
  auto options = FastOptions(tmp / "session", 3);
  options.calibration = true;
  auto report = RunCapture(camera, options);
  ASSERT_TRUE(report.ok()) << report.status().message();
  auto session = Session::Open(tmp / "session");
  ASSERT_TRUE(session.ok());
  ASSERT_EQ(session->ShotsOfKind("calib").size(), 3u);
  EXPECT_EQ(session->ShotsOfKind("calib")[0].file, "calib/calib_0001.jpg");
  for (const auto& r : session->ShotsOfKind("calib")) EXPECT_TRUE(r.flags.empty());  // no flash check for calib
}

TEST(TetheredCapture, BusyCameraIsRetriedWithBackoff) {
  const fs::path tmp = testing::MakeTempDir();
  FakeCameraOptions fo;
  fo.photos = MakePhotos(tmp / "photos");
  fo.busy_at = {{2, 3}, {4, 1}};
  FakeCamera camera(fo);
  auto report = RunCapture(camera, FastOptions(tmp / "session", 5));
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_TRUE(report->ok()) << report->error;
  EXPECT_EQ(report->retries, 4);
  EXPECT_EQ(camera.capture_attempts(), 9);
  EXPECT_EQ(report->shots[1].retries, 3);
  ExpectIntactSession(tmp / "session", 5, fo.photos);
}

TEST(TetheredCapture, CameraBusyForeverStopsWithShotsIntact) {
  const fs::path tmp = testing::MakeTempDir();
  FakeCameraOptions fo;
  fo.photos = MakePhotos(tmp / "photos");
  fo.busy_at = {{3, 1000}};
  FakeCamera camera(fo);
  auto options = FastOptions(tmp / "session", 5);
  options.retry.max_attempts = 4;
  auto report = RunCapture(camera, options);
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_FALSE(report->ok());
  EXPECT_EQ(report->stop_reason, "camera_not_responding");
  EXPECT_NE(report->error.find("gave up after 4 attempts"), std::string::npos) << report->error;
  ExpectIntactSession(tmp / "session", 2, fo.photos);
}

TEST(TetheredCapture, UnpluggedMidRunKeepsShotsAndResumeContinuesNumbering) {
  const fs::path tmp = testing::MakeTempDir();
  const fs::path root = tmp / "session";
  FakeCameraOptions fo;
  fo.photos = MakePhotos(tmp / "photos");
  fo.disconnect_after = 4;
  {
    FakeCamera camera(fo);
    auto report = RunCapture(camera, FastOptions(root, 10));
    ASSERT_TRUE(report.ok()) << report.status().message();
    EXPECT_FALSE(report->ok());
    EXPECT_EQ(report->stop_reason, "camera_gone");
    EXPECT_EQ(report->shots_captured, 4);
    EXPECT_NE(report->error.find("unplugged"), std::string::npos) << report->error;
    EXPECT_NE(report->error.find("--resume"), std::string::npos) << report->error;
    EXPECT_NE(report->error.find("4 shots taken this run"), std::string::npos) << report->error;
    ExpectIntactSession(root, 4, fo.photos);
  }
  std::map<std::string, std::string> before;
  for (const auto& name : FilesIn(root / "shots")) before[name] = Bytes(root / "shots" / name);

  // Without --resume the session is refused, never overwritten.
  fo.disconnect_after = -1;
  FakeCamera again(fo);
  auto refused = RunCapture(again, FastOptions(root, 3));
  EXPECT_FALSE(refused.ok());
  EXPECT_NE(refused.status().message().find("--resume"), std::string::npos) << refused.status().message();

  auto options = FastOptions(root, 3);
  options.resume = true;
  auto report = RunCapture(again, options);
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_TRUE(report->ok()) << report->error;
  EXPECT_EQ(report->first_index, 5);
  EXPECT_EQ(report->shots.front().file, "shots/shot_0005.jpg");
  auto manifest = ReadJsonFile(root / "session.json");
  ASSERT_TRUE(manifest.ok());
  ASSERT_EQ((*manifest)["capture_runs"].size(), 2u);  // one entry per run, with its provenance
  EXPECT_EQ((*manifest)["capture_runs"][0]["stop_reason"], "camera_gone");
  EXPECT_EQ((*manifest)["capture_runs"][1]["first_index"], 5);
  EXPECT_TRUE((*manifest)["capture_runs"][1]["provenance"]["options"]["resume"].get<bool>());
  ExpectIntactSession(root, 7, fo.photos);
  for (const auto& [name, bytes] : before) EXPECT_EQ(Bytes(root / "shots" / name), bytes) << name << " was modified";
}

TEST(TetheredCapture, DamagedDownloadIsFetchedAgain) {
  for (bool keeps_size : {false, true}) {
    SCOPED_TRACE(keeps_size ? "truncated file, consistent size" : "size mismatch");
    const fs::path tmp = testing::MakeTempDir() / (keeps_size ? "a" : "b");
    FakeCameraOptions fo;
    fo.photos = MakePhotos(tmp / "photos");
    fo.corrupt_download_at = {{2, 1}, {3, 2}};
    fo.corrupt_keeps_size = keeps_size;
    FakeCamera camera(fo);
    auto report = RunCapture(camera, FastOptions(tmp / "session", 4));
    ASSERT_TRUE(report.ok()) << report.status().message();
    EXPECT_TRUE(report->ok()) << report->error;
    EXPECT_EQ(report->retries, 3);
    EXPECT_EQ(camera.captures(), 4);  // a damaged download is fetched again, not shot again
    ExpectIntactSession(tmp / "session", 4, fo.photos);
  }
}

TEST(TetheredCapture, DownloadDamagedEveryTimeStopsWithoutAPartialShot) {
  const fs::path tmp = testing::MakeTempDir();
  FakeCameraOptions fo;
  fo.photos = MakePhotos(tmp / "photos");
  fo.corrupt_download_at = {{3, 1000}};
  FakeCamera camera(fo);
  auto options = FastOptions(tmp / "session", 5);
  options.retry.max_attempts = 3;
  auto report = RunCapture(camera, options);
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_FALSE(report->ok());
  EXPECT_NE(report->error.find("download incomplete"), std::string::npos) << report->error;
  ExpectIntactSession(tmp / "session", 2, fo.photos);  // no shot_0003, no temp file
}

TEST(TetheredCapture, DiskFullStopsWithShotsIntact) {
  const fs::path tmp = testing::MakeTempDir();
  FakeCameraOptions fo;
  fo.photos = MakePhotos(tmp / "photos");
  fo.disk_full_at = {3};
  FakeCamera camera(fo);
  auto report = RunCapture(camera, FastOptions(tmp / "session", 5));
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_EQ(report->stop_reason, "disk_full");
  EXPECT_NE(report->error.find("free disk space"), std::string::npos) << report->error;
  ExpectIntactSession(tmp / "session", 2, fo.photos);
}

TEST(TetheredCapture, CardFullStops) {
  const fs::path tmp = testing::MakeTempDir();
  FakeCameraOptions fo;
  fo.photos = MakePhotos(tmp / "photos");
  fo.card_capacity = 3;
  FakeCamera camera(fo);
  auto report = RunCapture(camera, FastOptions(tmp / "session", 5));
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_EQ(report->stop_reason, "card_full");
  ExpectIntactSession(tmp / "session", 3, fo.photos);
}

TEST(TetheredCapture, SettingsAreValidatedAppliedAndRecorded) {
  const fs::path tmp = testing::MakeTempDir();
  FakeCameraOptions fo;
  fo.photos = MakePhotos(tmp / "photos");
  FakeCamera camera(fo);

  CameraStatus bad_key = ValidateSettings(camera, {"iso=400", "isso=400"});
  EXPECT_EQ(bad_key.error, CameraError::kBadSetting);
  EXPECT_NE(bad_key.message.find("settable keys: iso, shutterspeed"), std::string::npos) << bad_key.message;
  CameraStatus bad_value = ValidateSettings(camera, {"iso=300"});
  EXPECT_EQ(bad_value.error, CameraError::kBadSetting);
  EXPECT_NE(bad_value.message.find("choices: 100, 200, 400, 800, 1600"), std::string::npos) << bad_value.message;
  EXPECT_EQ(ValidateSettings(camera, {"batterylevel=1"}).error, CameraError::kBadSetting);
  EXPECT_TRUE(ValidateSettings(camera, {"iso=400", "aperture=f/11"}).ok());

  auto options = FastOptions(tmp / "bad", 2);
  options.settings = {"iso=300"};
  auto rejected = RunCapture(camera, options);
  EXPECT_FALSE(rejected.ok());
  EXPECT_FALSE(fs::exists(tmp / "bad" / "session.json")) << "a rejected setting must not create a session";

  options = FastOptions(tmp / "session", 2);
  options.settings = {"iso=400", "shutterspeed = 1/250"};
  auto report = RunCapture(camera, options);
  ASSERT_TRUE(report.ok()) << report.status().message();
  ConfigEntry iso;
  ASSERT_TRUE(camera.GetConfig("iso", &iso).ok());
  EXPECT_EQ(iso.value, "400");
  auto session = Session::Open(tmp / "session");
  ASSERT_TRUE(session.ok());
  for (const auto& r : session->shots()) {
    EXPECT_EQ(r.settings.value("iso", ""), "400");
    EXPECT_EQ(r.settings.value("shutterspeed", ""), "1/250");
  }

  CaptureOptions invalid = FastOptions(tmp / "x", 0);
  EXPECT_NE(invalid.Check().find("--shots"), std::string::npos);
  invalid = FastOptions(tmp / "x", 1);
  invalid.settings = {"iso400"};
  EXPECT_NE(invalid.Check().find("key=value"), std::string::npos);
  invalid = FastOptions(tmp / "nothing-here", 1);
  invalid.resume = true;
  EXPECT_NE(invalid.Check().find("not a mesocap session"), std::string::npos);
}

TEST(TetheredCapture, RemoteModeDownloadsEachNewFileOnce) {
  const fs::path tmp = testing::MakeTempDir();
  FakeCameraOptions fo;
  fo.photos = MakePhotos(tmp / "photos");
  FakeCamera camera(fo);
  ASSERT_TRUE(camera.TriggerCapture().ok());
  ASSERT_TRUE(camera.TriggerCapture().ok());
  auto options = FastOptions(tmp / "session", 0);
  options.mode = CaptureMode::kRemote;
  options.remote_idle_timeout_s = 0.3;
  auto report = RunCapture(camera, options);
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_EQ(report->stop_reason, "idle_timeout");
  EXPECT_EQ(report->shots_captured, 2);
  ExpectIntactSession(tmp / "session", 2, fo.photos);
}

TEST(TetheredCapture, EnterModeShootsWhenReady) {
  const fs::path tmp = testing::MakeTempDir();
  FakeCameraOptions fo;
  fo.photos = MakePhotos(tmp / "photos");
  FakeCamera camera(fo);
  auto options = FastOptions(tmp / "session", 5);
  options.mode = CaptureMode::kEnter;
  auto report = RunCapture(camera, options, nullptr, [](int number, int total) { return number <= 3; });
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_EQ(report->stop_reason, "cancelled");
  ExpectIntactSession(tmp / "session", 3, fo.photos);
}

TEST(TetheredCapture, ResumeJournalsCompleteOrphansAndDropsTempFiles) {
  const fs::path tmp = testing::MakeTempDir();
  const fs::path root = tmp / "session";
  FakeCameraOptions fo;
  fo.photos = MakePhotos(tmp / "photos");
  {
    FakeCamera camera(fo);
    ASSERT_TRUE(RunCapture(camera, FastOptions(root, 3)).ok());
  }
  // A crash after the rename but before the journal line, and one in the middle of a download.
  fs::copy_file(fo.photos[0], root / "shots" / "shot_0004.jpg");
  {
    std::ofstream partial(root / "shots" / ".shot_0005.tmp999_0.jpg", std::ios::binary);
    partial << Bytes(fo.photos[1]).substr(0, 100);
  }
  {
    std::ofstream torn(root / "journal.jsonl", std::ios::app);
    torn << "{\"index\": 5, \"kind\": \"sh";  // a crash while appending
  }
  FakeCamera camera(fo);
  auto options = FastOptions(root, 2);
  options.resume = true;
  auto report = RunCapture(camera, options);
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_EQ(report->recovered, 1);
  EXPECT_EQ(report->removed_partial_files, 1);
  EXPECT_EQ(report->first_index, 5);
  // The torn line stays in the journal (ignored); the shots after it still parse.
  ExpectIntactSession(root, 6, fo.photos);
  auto session = Session::Open(root);
  ASSERT_TRUE(session.ok());
  EXPECT_EQ(session->torn_journal_lines(), 1);
  const auto shots = session->ShotsOfKind("shot");
  const auto recovered = std::find_if(shots.begin(), shots.end(), [](const ShotRecord& r) { return r.index == 4; });
  ASSERT_NE(recovered, shots.end());
  EXPECT_NE(std::find(recovered->flags.begin(), recovered->flags.end(), "recovered"), recovered->flags.end());
}

TEST(TetheredCapture, DeletesFromTheCameraOnlyWhenAskedAndAfterTheShotIsSafe) {
  const fs::path tmp = testing::MakeTempDir();
  FakeCameraOptions fo;
  fo.photos = MakePhotos(tmp / "photos");
  FakeCamera keep(fo);
  ASSERT_TRUE(RunCapture(keep, FastOptions(tmp / "kept", 3)).ok());
  EXPECT_EQ(keep.files_on_card(), 3);
  FakeCamera del(fo);
  auto options = FastOptions(tmp / "deleted", 3);
  options.delete_from_camera = true;
  auto report = RunCapture(del, options);
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_TRUE(report->warnings.empty());
  EXPECT_EQ(del.files_on_card(), 0);
  ExpectIntactSession(tmp / "deleted", 3, fo.photos);
}

TEST(TetheredCapture, OneWriterPerSession) {
  const fs::path tmp = testing::MakeTempDir();
  const fs::path root = tmp / "session";
  FakeCameraOptions fo;
  fo.photos = MakePhotos(tmp / "photos");
  FakeCamera camera(fo);
  ASSERT_TRUE(RunCapture(camera, FastOptions(root, 1)).ok());
  auto options = FastOptions(root, 1);
  options.resume = true;
  {
    // Another writer holding the session's lock (flock locks are per open file description).
    auto held = SessionLock::Acquire(root, "process");
    ASSERT_TRUE(held.ok()) << held.status().message();
    auto refused = RunCapture(camera, options);
    EXPECT_FALSE(refused.ok());
    if (!refused.ok()) {
      EXPECT_NE(refused.status().message().find("is being written by mesocap process"), std::string::npos)
          << refused.status().message();
    }
  }
  EXPECT_TRUE(RunCapture(camera, options).ok());
  ExpectIntactSession(root, 2, fo.photos);
}

// Child side of the kill test: runs only when the parent test re-executes this binary.
TEST(TetheredCaptureChild, CapturesUntilKilled) {
  const char* out = std::getenv("MESOCAP_KILL_TEST_OUT");
  const char* photos = std::getenv("MESOCAP_KILL_TEST_PHOTOS");
  if (!out || !photos) GTEST_SKIP() << "runs only as the child of TetheredCapture.KillNineThenResume";
  FakeCameraOptions fo;
  for (int k = 0; k < 3; ++k) fo.photos.push_back(fs::path(photos) / ("photo_" + std::to_string(k) + ".jpg"));
  fo.capture_delay_s = 0.01;
  FakeCamera camera(fo);
  auto options = FastOptions(out, 20);
  options.resume = fs::exists(fs::path(out) / "session.json");
  auto report = RunCapture(camera, options);
  ASSERT_TRUE(report.ok()) << report.status().message();
}

TEST(TetheredCapture, KillNineThenResume) {
  const fs::path tmp = testing::MakeTempDir();
  const auto photos = MakePhotos(tmp / "photos");
  std::mt19937 rng(testing::SeedFromTestName());
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  for (int round = 0; round < 6; ++round) {
    const fs::path root = tmp / ("session" + std::to_string(round));
    // A 20-shot run takes ~0.5 s once started (10 ms capture + ~15 ms of fsyncs per shot).
    std::uniform_int_distribution<int> kill_ms(0, 450);
    const int delay_ms = kill_ms(rng);
    SCOPED_TRACE("kill after " + std::to_string(delay_ms) + " ms");
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      // A fresh process (exec) so no thread of this one is inherited in a locked state.
      ::setenv("MESOCAP_KILL_TEST_OUT", root.c_str(), 1);
      ::setenv("MESOCAP_KILL_TEST_PHOTOS", (tmp / "photos").c_str(), 1);
      ::execl(self.c_str(), self.c_str(), "--gtest_filter=TetheredCaptureChild.*", "--gtest_brief=1",
              static_cast<char*>(nullptr));
      ::_exit(127);
    }
    // Count from the moment the session exists, not from the child's start-up.
    for (int i = 0; i < 2000 && !fs::exists(root / "session.json"); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);

    // Whatever moment it died at: the journal parses, every journaled shot's file is whole.
    int done_before = 0;
    if (fs::exists(root / "session.json")) {
      auto session = Session::Open(root);
      ASSERT_TRUE(session.ok()) << session.status().message();
      EXPECT_LE(session->torn_journal_lines(), 1);
      done_before = int(session->ShotsOfKind("shot").size());
      for (const auto& r : session->ShotsOfKind("shot")) {
        const std::string bytes = Bytes(root / r.file);
        EXPECT_TRUE(bytes == Bytes(photos[0]) || bytes == Bytes(photos[1]) || bytes == Bytes(photos[2])) << r.file;
      }
    }
    // Resume until 20 shots are in: no index twice, no partial file, nothing overwritten.
    FakeCameraOptions fo;
    fo.photos = photos;
    FakeCamera camera(fo);
    auto options = FastOptions(root, 20);
    options.resume = fs::exists(root / "session.json");
    auto opened = options.resume ? Session::Open(root) : StatusOr<Session>(Status::Error("none"));
    const int present = opened.ok() ? opened->NextIndex("shot") - 1 : 0;
    options.shots = std::max(1, 20 - present);
    auto report = RunCapture(camera, options);
    ASSERT_TRUE(report.ok()) << report.status().message();
    ASSERT_TRUE(report->ok()) << report->error;
    EXPECT_GE(present, done_before);
    std::printf("kill -9 after %d ms: %d shots journaled, %d files present, %d recovered, %d temp files removed\n",
                delay_ms, done_before, present, report->recovered, report->removed_partial_files);
    ExpectIntactSession(root, present >= 20 ? present + 1 : 20, photos);
  }
}

}  // namespace
}  // namespace mesocap

#include "capture/import.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <fstream>
#include <map>

#include "core/atomic_file.h"
#include "core/image_io.h"
#include "core/json.h"
#include "core/session.h"
#include "tests/testing.h"

namespace mesocap {
namespace {
namespace fs = std::filesystem;

// A small image unlike the others for each `k`, so every file's bytes differ.
Image TestImage(int k) {
  Image image(40, 30, 3);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x)
      for (int c = 0; c < 3; ++c) image.at(x, y, c) = float((x * (k + 1) + y * (c + 2) + 17 * k) % 64) / 64.0f;
  return image;
}

void WritePhoto(const fs::path& path, int k, const std::string& exif_time) {
  ImageWriteOptions o;
  o.format = DefaultFormatFor(path);
  if (!exif_time.empty()) {
    o.attributes["Exif:DateTimeOriginal"] = exif_time;
    o.attributes["DateTime"] = exif_time;
  }
  o.attributes["Make"] = std::string("TestCam");
  o.attributes["Model"] = std::string("T1");
  ASSERT_TRUE(WriteImage(path, TestImage(k), o).ok()) << path;
}

// Sets a file's modification time to `day` days and `s` seconds after 2026-01-01 00:00 UTC.
void SetFileTime(const fs::path& path, int day, int s = 0) {
  const auto t = std::chrono::sys_seconds(std::chrono::seconds(1767225600LL + day * 86400LL + s));
  fs::last_write_time(path, std::chrono::file_clock::from_sys(t));
}

std::string Bytes(const fs::path& path) {
  auto text = ReadTextFile(path);
  EXPECT_TRUE(text.ok()) << text.status().message();
  return text.ok() ? *text : "";
}

struct Snapshot {
  std::string bytes;
  fs::file_time_type mtime;
  bool operator==(const Snapshot&) const = default;
};

std::map<std::string, Snapshot> SnapshotFolder(const fs::path& dir) {
  std::map<std::string, Snapshot> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file()) out[e.path().filename().string()] = {Bytes(e.path()), fs::last_write_time(e.path())};
  return out;
}

// The folder of the "must hold" case. Names run a..e; capture times run d, b, c, e, a;
// file times run the other way round, so neither name nor file order can pass for EXIF order.
// e.jpg has no EXIF time and is placed by its file time (2026-01-03) between the Jan 1 and Jan 5
// shots. Plus a truncated JPEG, a text file, an empty file and a sub-folder.
fs::path MakePhotoFolder(const fs::path& root) {
  const fs::path dir = root / "photos";
  fs::create_directories(dir / "sub");
  WritePhoto(dir / "a.jpg", 0, "2026:01:05 09:00:00");
  WritePhoto(dir / "b.jpg", 1, "2026:01:01 12:00:10");
  WritePhoto(dir / "c.tif", 2, "2026:01:01 12:00:20");
  WritePhoto(dir / "d.png", 3, "2026:01:01 12:00:00");
  WritePhoto(dir / "e.jpg", 4, "");
  SetFileTime(dir / "a.jpg", 1, 0);
  SetFileTime(dir / "b.jpg", 6, 3);
  SetFileTime(dir / "c.tif", 6, 2);
  SetFileTime(dir / "d.png", 6, 4);
  SetFileTime(dir / "e.jpg", 2, 0);

  WritePhoto(dir / "truncated.jpg", 5, "2026:01:01 12:00:05");
  const std::string full = Bytes(dir / "truncated.jpg");
  std::ofstream(dir / "truncated.jpg", std::ios::binary | std::ios::trunc) << full.substr(0, full.size() / 2);
  std::ofstream(dir / "notes.txt") << "lighting: flash on camera, 24 shots\n";
  std::ofstream(dir / "empty.jpg");
  return dir;
}

std::string Reason(const ImportReport& report, const std::string& name) {
  for (const auto& s : report.skipped)
    if (s.source.filename() == name) return s.reason;
  return "<not skipped>";
}

TEST(Import, TruncatedJpegPassesHeaderCheckButNotDecode) {
  // Why import decodes every image: the header alone does not reveal the truncation.
  const fs::path dir = MakePhotoFolder(testing::MakeTempDir());
  EXPECT_TRUE(ReadImageInfo(dir / "truncated.jpg").ok());
  EXPECT_FALSE(ReadImage(dir / "truncated.jpg").ok());
}

TEST(Import, OrdersByCaptureTimeAndSkipsBadFiles) {
  const fs::path root = testing::MakeTempDir();
  const fs::path photos = MakePhotoFolder(root);
  const auto before = SnapshotFolder(photos);

  ImportOptions options;
  options.photo_dir = photos;
  options.out = root / "session";
  int last_done = 0, calls = 0;
  auto report = ImportPhotoFolder(options, [&](int done, int total, const std::string&) {
    EXPECT_GE(done, last_done);
    EXPECT_LE(done, total);
    last_done = done;
    ++calls;
    return true;
  });
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_GT(calls, 0);

  // Good photos in capture-time order; e.jpg by its file time.
  ASSERT_EQ(report->shots_imported, 5);
  ASSERT_EQ(report->imported.size(), 5u);
  const std::vector<std::string> expected_sources = {"d.png", "b.jpg", "c.tif", "e.jpg", "a.jpg"};
  const std::vector<std::string> expected_files = {"shots/shot_0001.png", "shots/shot_0002.jpg",
                                                   "shots/shot_0003.tif", "shots/shot_0004.jpg",
                                                   "shots/shot_0005.jpg"};
  for (size_t i = 0; i < 5; ++i) {
    const ImportedPhoto& p = report->imported[i];
    EXPECT_EQ(p.source.filename().string(), expected_sources[i]) << i;
    EXPECT_EQ(p.file, expected_files[i]) << i;
    EXPECT_EQ(p.index, int(i) + 1);
    EXPECT_EQ(p.kind, "shot");
    EXPECT_EQ(p.time_source, p.source.filename() == "e.jpg" ? "file_mtime" : "exif:DateTimeOriginal") << p.source;
    // Bytes identical to the original.
    EXPECT_EQ(Bytes(root / "session" / p.file), before.at(expected_sources[i]).bytes) << p.file;
  }
  EXPECT_EQ(report->imported[0].capture_time, "2026-01-01T12:00:00");
  EXPECT_EQ(report->imported[3].capture_time, "2026-01-03T00:00:00Z");

  // The others listed with reasons.
  ASSERT_EQ(report->skipped.size(), 4u);
  EXPECT_NE(Reason(*report, "empty.jpg").find("empty"), std::string::npos) << Reason(*report, "empty.jpg");
  EXPECT_NE(Reason(*report, "truncated.jpg"), "<not skipped>");
  EXPECT_FALSE(Reason(*report, "truncated.jpg").empty());
  EXPECT_NE(Reason(*report, "truncated.jpg").find("JPEG"), std::string::npos) << Reason(*report, "truncated.jpg");
  EXPECT_NE(Reason(*report, "notes.txt").find("not an image"), std::string::npos) << Reason(*report, "notes.txt");
  EXPECT_NE(Reason(*report, "sub").find("folder"), std::string::npos);
  for (const auto& s : report->skipped) EXPECT_EQ(s.reason.find(photos.string()), std::string::npos) << s.reason;
  EXPECT_FALSE(report->warnings.empty());  // e.jpg has no EXIF time

  // Originals untouched (bytes and file times), nothing added to the photo folder.
  EXPECT_EQ(SnapshotFolder(photos), before);

  // The journal holds the same shots in the same order; the report is beside them.
  auto session = Session::Open(root / "session");
  ASSERT_TRUE(session.ok()) << session.status().message();
  ASSERT_EQ(session->shots().size(), 5u);
  for (size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(session->shots()[i].file, expected_files[i]);
    EXPECT_EQ(session->shots()[i].exif.value("Make", ""), "TestCam");
  }
  EXPECT_EQ(session->shots()[3].flags, std::vector<std::string>{"time_from_file_mtime"});
  EXPECT_EQ(session->manifest().value("source", ""), "import");
  auto json = ReadJsonFile(root / "session" / "import_report.json");
  ASSERT_TRUE(json.ok()) << json.status().message();
  EXPECT_EQ((*json)["imported_count"], 5);
  EXPECT_EQ((*json)["skipped"].size(), 4u);
  EXPECT_EQ((*json)["skipped"][0]["source"].get<std::string>().empty(), false);
  EXPECT_TRUE((*json)["skipped"][0].contains("reason"));
  EXPECT_TRUE(json->contains("total_s"));
  EXPECT_NE(report->Brief().find("imported 5 shots"), std::string::npos) << report->Brief();

  // No staging folder left behind.
  for (const auto& e : fs::directory_iterator(root))
    EXPECT_NE(e.path().filename().string().rfind(".session", 0), 0u) << e.path();
}

TEST(Import, HardlinksOnTheSameFileSystemAndCopiesOnRequest) {
  const fs::path root = testing::MakeTempDir();
  const fs::path photos = MakePhotoFolder(root);

  ImportOptions options;
  options.photo_dir = photos;
  options.out = root / "linked";
  auto linked = ImportPhotoFolder(options);
  ASSERT_TRUE(linked.ok()) << linked.status().message();
  EXPECT_EQ(linked->hardlinked, 5);
  for (const auto& p : linked->imported) EXPECT_TRUE(fs::equivalent(p.source, root / "linked" / p.file));

  options.out = root / "copied";
  options.link_mode = LinkMode::kCopy;
  const auto before = SnapshotFolder(photos);
  auto copied = ImportPhotoFolder(options);
  ASSERT_TRUE(copied.ok()) << copied.status().message();
  EXPECT_EQ(copied->copied, 5);
  EXPECT_EQ(copied->hardlinked, 0);
  for (const auto& p : copied->imported) {
    const fs::path dest = root / "copied" / p.file;
    EXPECT_FALSE(fs::equivalent(p.source, dest));
    EXPECT_EQ(Bytes(dest), Bytes(p.source));
    EXPECT_EQ(fs::last_write_time(dest), fs::last_write_time(p.source));
  }
  // No temp files left in the session.
  for (const auto& e : fs::recursive_directory_iterator(root / "copied"))
    EXPECT_NE(e.path().filename().string()[0], '.') << e.path();
  EXPECT_EQ(SnapshotFolder(photos), before);

  LinkMode mode;
  EXPECT_TRUE(StringToLinkMode("copy", &mode));
  EXPECT_EQ(mode, LinkMode::kCopy);
  EXPECT_TRUE(StringToLinkMode(LinkModeToString(LinkMode::kHardlink), &mode));
  EXPECT_EQ(mode, LinkMode::kHardlink);
  EXPECT_FALSE(StringToLinkMode("symlink", &mode));
}

TEST(Import, HardlinkFallsBackToCopyAcrossFileSystems) {
  // /dev/shm is a tmpfs on Linux; a hard link from there into the temp folder fails (EXDEV).
  const fs::path root = testing::MakeTempDir();
  const fs::path shm = "/dev/shm";
  struct stat a {}, b {};
  if (::stat(shm.c_str(), &a) != 0 || ::stat(root.c_str(), &b) != 0 || a.st_dev == b.st_dev)
    GTEST_SKIP() << "no second file system to import from";
  const fs::path other = shm / root.filename();
  fs::remove_all(other);
  const fs::path photos = MakePhotoFolder(other);

  ImportOptions options;
  options.photo_dir = photos;
  options.out = root / "session";
  auto report = ImportPhotoFolder(options);
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_EQ(report->hardlinked, 0);
  EXPECT_EQ(report->copied, 5);
  for (const auto& p : report->imported) {
    EXPECT_EQ(p.method, "copy");
    EXPECT_EQ(Bytes(root / "session" / p.file), Bytes(p.source));
  }
  fs::remove_all(other);
}

TEST(Import, CalibrationShotsFromTheirOwnFolder) {
  const fs::path root = testing::MakeTempDir();
  const fs::path photos = MakePhotoFolder(root);
  const fs::path calib = root / "calib_photos";
  fs::create_directories(calib);
  WritePhoto(calib / "board1.jpg", 10, "2026:01:01 11:00:09");
  WritePhoto(calib / "board2.jpg", 11, "2026:01:01 11:00:01");
  std::ofstream(calib / "readme.txt") << "checkerboard 9x6";

  ImportOptions options;
  options.photo_dir = photos;
  options.calibration_dir = calib;
  options.out = root / "session";
  auto report = ImportPhotoFolder(options);
  ASSERT_TRUE(report.ok()) << report.status().message();
  EXPECT_EQ(report->calib_shots_imported, 2);
  EXPECT_EQ(report->shots_imported, 5);
  EXPECT_EQ(report->skipped.size(), 5u);
  EXPECT_NE(Reason(*report, "readme.txt"), "<not skipped>");

  auto session = Session::Open(root / "session");
  ASSERT_TRUE(session.ok());
  const auto shots = session->ShotsOfKind("calib");
  ASSERT_EQ(shots.size(), 2u);
  EXPECT_EQ(shots[0].file, "calib/calib_0001.jpg");
  EXPECT_EQ(Bytes(root / "session" / shots[0].file), Bytes(calib / "board2.jpg"));
  EXPECT_EQ(Bytes(root / "session" / shots[1].file), Bytes(calib / "board1.jpg"));
  EXPECT_EQ(session->ShotsOfKind("shot").size(), 5u);
}

TEST(Import, RefusesNonEmptyOutput) {
  const fs::path root = testing::MakeTempDir();
  ImportOptions options;
  options.photo_dir = MakePhotoFolder(root);
  options.out = root / "busy";
  fs::create_directories(options.out);
  std::ofstream(options.out / "keep.txt") << "mine";
  EXPECT_NE(options.Check().find("not empty"), std::string::npos) << options.Check();
  auto report = ImportPhotoFolder(options);
  ASSERT_FALSE(report.ok());
  EXPECT_NE(report.status().message().find("not empty"), std::string::npos) << report.status().message();
  EXPECT_EQ(Bytes(options.out / "keep.txt"), "mine");
  EXPECT_EQ(std::distance(fs::directory_iterator(options.out), fs::directory_iterator()), 1);

  // An existing empty folder is fine.
  options.out = root / "empty_out";
  fs::create_directories(options.out);
  EXPECT_EQ(options.Check(), "");
  EXPECT_TRUE(ImportPhotoFolder(options).ok());
  EXPECT_TRUE(fs::exists(options.out / "import_report.json"));
}

TEST(Import, MissingOrBadFoldersGiveClearErrors) {
  const fs::path root = testing::MakeTempDir();
  ImportOptions options;
  options.photo_dir = root / "no_such_dir";
  options.out = root / "session";
  auto report = ImportPhotoFolder(options);
  ASSERT_FALSE(report.ok());
  EXPECT_NE(report.status().message().find("no_such_dir"), std::string::npos);
  EXPECT_NE(report.status().message().find("no such folder"), std::string::npos) << report.status().message();
  EXPECT_FALSE(fs::exists(root / "session"));

  std::ofstream(root / "file.jpg") << "x";
  options.photo_dir = root / "file.jpg";
  EXPECT_NE(options.Check().find("not a folder"), std::string::npos) << options.Check();

  options.photo_dir = MakePhotoFolder(root);
  options.calibration_dir = root / "no_calib";
  EXPECT_NE(options.Check().find("no_calib"), std::string::npos) << options.Check();
  options.calibration_dir = options.photo_dir;
  EXPECT_NE(options.Check().find("differ"), std::string::npos) << options.Check();
  options.calibration_dir.clear();
  options.out.clear();
  EXPECT_NE(options.Check().find("--out"), std::string::npos) << options.Check();

  // A folder with nothing importable is an error naming the folder, and leaves no session.
  const fs::path junk = root / "junk";
  fs::create_directories(junk);
  std::ofstream(junk / "a.txt") << "not a photo";
  std::ofstream(junk / "b.jpg");
  options.photo_dir = junk;
  options.out = root / "junk_session";
  report = ImportPhotoFolder(options);
  ASSERT_FALSE(report.ok());
  EXPECT_NE(report.status().message().find("no importable photo"), std::string::npos) << report.status().message();
  EXPECT_FALSE(fs::exists(options.out));
}

TEST(Import, CancelLeavesNothing) {
  const fs::path root = testing::MakeTempDir();
  ImportOptions options;
  options.photo_dir = MakePhotoFolder(root);
  options.out = root / "session";
  int calls = 0;
  auto report = ImportPhotoFolder(options, [&](int, int, const std::string&) { return ++calls < 12; });
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.status().message(), "cancelled");
  EXPECT_FALSE(fs::exists(options.out));
  for (const auto& e : fs::directory_iterator(root)) EXPECT_NE(e.path().filename().string()[0], '.') << e.path();
}

TEST(Import, FlashNotFiredIsFlaggedAndSubsecondsOrder) {
  const fs::path root = testing::MakeTempDir();
  const fs::path dir = root / "photos";
  fs::create_directories(dir);
  // Same second, told apart by SubsecTimeOriginal; x.jpg's flash did not fire.
  for (const auto& [name, subsec, flash] : std::vector<std::tuple<std::string, std::string, int>>{
           {"x.jpg", "70", 0}, {"y.jpg", "25", 1}}) {
    ImageWriteOptions o;
    o.attributes["Exif:DateTimeOriginal"] = std::string("2026:02:02 10:00:00");
    o.attributes["Exif:SubsecTimeOriginal"] = subsec;
    o.attributes["Exif:Flash"] = flash;
    ASSERT_TRUE(WriteImage(dir / name, TestImage(name[0]), o).ok());
  }
  ImportOptions options;
  options.photo_dir = dir;
  options.out = root / "session";
  auto report = ImportPhotoFolder(options);
  ASSERT_TRUE(report.ok()) << report.status().message();
  ASSERT_EQ(report->imported.size(), 2u);
  EXPECT_EQ(report->imported[0].source.filename(), "y.jpg");
  EXPECT_EQ(report->imported[0].capture_time, "2026-02-02T10:00:00.250");
  auto session = Session::Open(options.out);
  ASSERT_TRUE(session.ok());
  EXPECT_TRUE(session->shots()[0].flags.empty());
  EXPECT_EQ(session->shots()[1].flags, std::vector<std::string>{"flash_not_fired"});
}

}  // namespace
}  // namespace mesocap

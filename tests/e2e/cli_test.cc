// The real CLI as a script would use it: exit codes it can trust and one-line reasons.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include "core/image_io.h"
#include "core/json.h"
#include "core/session_layout.h"
#include "formats/lp_file.h"
#include "tests/testing.h"

namespace mesocap {
namespace {
namespace fs = std::filesystem;

int Lines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }

TEST(Cli, VersionAndHelp) {
  std::string out;
  EXPECT_EQ(testing::RunMesocap("--version", &out), 0);
  EXPECT_NE(out.find("mesocap 0."), std::string::npos);
  EXPECT_EQ(testing::RunMesocap("simulate --help", &out), 0);
  EXPECT_NE(out.find("--material"), std::string::npos);
  EXPECT_NE(testing::RunMesocap("", &out), 0);
  EXPECT_NE(testing::RunMesocap("no-such-verb", &out), 0);
}

// Every subcommand the program lists answers --help.
TEST(Cli, EveryCommandAnswersHelp) {
  std::string top;
  ASSERT_EQ(testing::RunMesocap("--help", &top), 0);
  std::istringstream lines(top.substr(top.find("Subcommands:")));
  std::string line, out;
  std::getline(lines, line);
  int commands = 0;
  while (std::getline(lines, line))
    if (line.size() > 2 && line[2] != ' ') {
      const std::string name = line.substr(2, line.find(' ', 2) - 2);
      EXPECT_EQ(testing::RunMesocap(name + " --help", &out), 0) << name;
      EXPECT_NE(out.find("Usage"), std::string::npos) << name << ": " << out;
      ++commands;
    }
  EXPECT_GE(commands, 15);
}

// `mesocap layout --json` gives scripts the paths the program itself uses; the text form joins
// them to the session as given.
TEST(Cli, LayoutPrintsThePathsTheProgramUses) {
  const fs::path session = testing::MakeTempDir() / "s1";
  std::string out;
  ASSERT_EQ(testing::RunMesocap("layout " + session.string() + " --json", &out), 0) << out;
  const Json printed = Json::parse(out);
  const SessionLayout layout(session);
  EXPECT_EQ(printed["root"], fs::absolute(session).lexically_normal().string());
  EXPECT_EQ(printed["calibration"]["rig"], layout.Relative(layout.calibration().rig()));
  EXPECT_EQ(printed["slices"]["index"], layout.Relative(layout.slices().index()));
  EXPECT_EQ(printed["export"]["gltf"]["material"], layout.Relative(layout.exports().gltf().material()));
  EXPECT_EQ(printed, layout.ToJson());
  ASSERT_EQ(testing::RunMesocap("layout " + session.string(), &out), 0) << out;
  EXPECT_NE(out.find("calibration.rig\t" + layout.calibration().rig().string() + "\n"), std::string::npos) << out;
  EXPECT_NE(testing::RunMesocap("layout", &out), 0) << "the session is required";
}

// The shared libraries the dynamic loader opened for `mesocap ARGS` (LD_DEBUG=files), as text.
std::string LoadedLibraries(const std::string& args) {
  const std::string command = "LD_DEBUG=files " + testing::MesocapBinary() + " " + args + " 2>&1 >/dev/null";
  std::string out;
  FILE* pipe = popen(command.c_str(), "r");
  char buffer[4096];
  for (size_t n; pipe && (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;) out.append(buffer, n);
  if (pipe) pclose(pipe);
  return out;
}

// OpenImageIO (and its ~260 libraries) is loaded by the first image that needs it, never at start
// (core/image_codec.h): a command that reads no such image starts in milliseconds.
TEST(Cli, OpenImageIoIsLoadedOnlyByAnImageThatNeedsIt) {
  const std::string version = LoadedLibraries("--version");
  ASSERT_NE(version.find("libc.so"), std::string::npos) << "LD_DEBUG gave no list: " << version;
  EXPECT_EQ(version.find("libOpenImageIO"), std::string::npos);
  EXPECT_EQ(LoadedLibraries("fit-ptm --help").find("libOpenImageIO"), std::string::npos);
  // An RTI set of JPEGs: fit-ptm decodes them with libjpeg and writes the .ptm itself.
  const auto dir = testing::MakeTempDir();
  std::vector<LpEntry> entries;
  for (int k = 0; k < 8; ++k) {
    const double azimuth = k * M_PI / 4, elevation = k % 2 ? 0.6 : 1.0;
    const Eigen::Vector3d light(std::cos(azimuth) * std::cos(elevation), std::sin(azimuth) * std::cos(elevation),
                                std::sin(elevation));
    entries.push_back({dir / ("shot" + std::to_string(k) + ".jpg"), light});
    ASSERT_TRUE(WriteImage(entries.back().image, Image(16, 16, 3, float(0.2 + 0.6 * light.z()))).ok());
  }
  ASSERT_TRUE(WriteLpFile(dir / "capture.lp", entries).ok());
  const std::string fit = LoadedLibraries("fit-ptm --lp " + (dir / "capture.lp").string() + " --out " +
                                          (dir / "out.ptm").string() + " --no-progress");
  ASSERT_TRUE(fs::exists(dir / "out.ptm")) << fit.substr(fit.size() > 2000 ? fit.size() - 2000 : 0);
  EXPECT_EQ(fit.find("libOpenImageIO"), std::string::npos);
  // A PNG needs it: writing one loads the module and OpenImageIO with it.
  const std::string png = LoadedLibraries("relight " + (dir / "out.ptm").string() + " --out " + (dir / "x.png").string() +
                                          " --light 0,0,1");
  EXPECT_TRUE(fs::exists(dir / "x.png"));
  EXPECT_NE(png.find("libmesocap_oiio"), std::string::npos);
  EXPECT_NE(png.find("libOpenImageIO"), std::string::npos);
}

// The front parses the command line alone (app/commands.h): help and version open none of the
// libraries the commands need, and the commands module only once a command runs.
TEST(Cli, HelpAndVersionLoadOnlyTheFront) {
  for (const std::string args : {"--version", "--help", "process --help", "synth --help"}) {
    const std::string loaded = LoadedLibraries(args);
    ASSERT_NE(loaded.find("libc.so"), std::string::npos) << "LD_DEBUG gave no list: " << loaded;
    for (const char* library : {"libmesocap_commands", "libopencv", "libceres", "libgphoto2", "libtbb", "libapriltag"})
      EXPECT_EQ(loaded.find(library), std::string::npos) << args << " loads " << library;
  }
  const auto dir = testing::MakeTempDir();
  const std::string run = LoadedLibraries("relight " + (dir / "missing.ptm").string() + " --out " +
                                          (dir / "x.jpg").string() + " --light 0,0,1");
  EXPECT_NE(run.find("libmesocap_commands"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "x.jpg"));
}

TEST(Cli, BadSimulateOptionsFailWithOneLine) {
  const auto dir = testing::MakeTempDir();
  std::string out;
  EXPECT_EQ(testing::RunMesocap("simulate --out " + (dir / "a").string() + " --material velvet --no-progress", &out), 2);
  EXPECT_EQ(Lines(out), 1) << out;
  EXPECT_NE(out.find("unknown material 'velvet'"), std::string::npos) << out;
  EXPECT_EQ(testing::RunMesocap("simulate --out " + (dir / "a").string() + " --width 5 --no-progress", &out), 2);
  EXPECT_EQ(Lines(out), 1) << out;
  std::ofstream(dir / "full" / "x").flush();
  fs::create_directories(dir / "full");
  std::ofstream(dir / "full" / "x") << "x";
  EXPECT_EQ(testing::RunMesocap("simulate --out " + (dir / "full").string() + " --no-progress", &out), 2);
  EXPECT_NE(out.find("not empty"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir / "a"));
}

TEST(Cli, WriteFailureMidRunLeavesNothingThatLooksComplete) {
  // A file-size limit makes every write past 2 MB fail, as a full disk would.
  const auto dir = testing::MakeTempDir();
  const std::string cmd = "bash -c \"trap '' XFSZ; ulimit -f 2048; exec " + testing::MesocapBinary() +
                          " simulate --out " + (dir / "s").string() +
                          " --shots 4 --calib-shots 0 --width 3000 --height 2000 --format exr --no-progress\" 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  char buf[4096];
  std::string out;
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) out.append(buf, n);
  const int status = ::pclose(pipe);
  EXPECT_EQ(WEXITSTATUS(status), 1) << out;
  EXPECT_EQ(Lines(out), 1) << out;
  EXPECT_NE(out.find("shot_0001.exr"), std::string::npos) << out;
  EXPECT_TRUE(fs::is_empty(dir)) << "a failed run must not leave a session or its staging folder";
}

TEST(Cli, TrueBtfWritesAnExrWithDirections) {
  const auto dir = testing::MakeTempDir();
  std::string out;
  ASSERT_EQ(testing::RunMesocap("simulate --true-btf --material flat --theta-i 60 --phi-i 10 --theta-o 30 --phi-o 0 "
                                "--size 64 --out " + (dir / "s.exr").string(), &out), 0) << out;
  ImageInfo info;
  auto im = ReadImage(dir / "s.exr", {}, &info);
  ASSERT_TRUE(im.ok());
  EXPECT_EQ(im->width(), 64);
  EXPECT_FLOAT_EQ(std::get<float>(info.attributes.at("mesocap:theta_i_deg")), 60.0f);
  EXPECT_NEAR(im->at(10, 10, 0), 0.5 / M_PI * 0.5, 0.005 * 0.5 / M_PI * 0.5);
}

TEST(Cli, ImportSkipsBadFilesListsThemAndExitsZero) {
  const auto dir = testing::MakeTempDir();
  const auto photos = dir / "photos";
  fs::create_directories(photos);
  Image im(320, 240, 3, 0.4f);
  // Capture times run opposite to the names.
  for (int k = 0; k < 3; ++k) {
    ImageWriteOptions w;
    w.attributes["Exif:DateTimeOriginal"] = "2026:03:01 10:00:0" + std::to_string(5 - k);
    ASSERT_TRUE(WriteImage(photos / ("p" + std::to_string(k) + ".jpg"), im, w).ok());
  }
  fs::copy_file(photos / "p0.jpg", photos / "cut.jpg");
  fs::resize_file(photos / "cut.jpg", fs::file_size(photos / "p0.jpg") / 2);
  std::ofstream(photos / "notes.txt") << "hello";
  std::ofstream(photos / "empty.jpg").close();
  std::string out;
  ASSERT_EQ(testing::RunMesocap("import " + photos.string() + " --out " + (dir / "s").string() + " --no-progress", &out), 0) << out;
  for (const char* name : {"cut.jpg", "notes.txt", "empty.jpg"}) EXPECT_NE(out.find(name), std::string::npos) << out;
  auto report = ReadJsonFile(dir / "s" / "import_report.json");
  ASSERT_TRUE(report.ok());
  const Json& imported = report->at("imported");
  ASSERT_EQ(imported.size(), 3u);
  EXPECT_NE(imported[0].at("source").get<std::string>().find("p2.jpg"), std::string::npos);
  EXPECT_NE(imported[2].at("source").get<std::string>().find("p0.jpg"), std::string::npos);
  EXPECT_EQ(report->at("skipped").size(), 3u);
  // A second import into the same folder is refused.
  EXPECT_EQ(testing::RunMesocap("import " + photos.string() + " --out " + (dir / "s").string() + " --no-progress", &out), 2);
}

// A lab's tethered session with guidance: checkerboard shots first, then flash shots, each
// followed by where the flash was and where it is needed next; the virtual photographer follows.
TEST(Cli, CaptureGuidesTheFlashAfterEachShot) {
  const auto dir = testing::MakeTempDir();
  const std::string session = (dir / "s").string();
  const std::string camera = " --camera virtual --port virtual:seed=41,width=1200,height=800,shots=20,calib-shots=10";
  std::string out;
  ASSERT_EQ(testing::RunMesocap("capture --out " + session + camera + " --calibration --set subject=checkerboard --shots 10 "
                                "--no-progress", &out), 0) << out;
  ASSERT_EQ(testing::RunMesocap("capture --out " + session + camera +
                                    " --resume --shots 8 --guide-after 5 --follow-guide --guide-images half_turn",
                                &out), 0) << out;
  EXPECT_NE(out.find("shots/shot_0001.jpg: flash position unknown"), std::string::npos) << out;
  EXPECT_NE(out.find("located after 5 flash shots (1 so far)"), std::string::npos) << out;
  for (const char* shot : {"shot_0005.jpg: flash ", "shot_0008.jpg: flash "}) EXPECT_NE(out.find(shot), std::string::npos) << out;
  EXPECT_NE(out.find("next 1: move the flash"), std::string::npos) << out;
  auto coverage = ReadJsonFile(dir / "s" / "coverage" / "coverage.json");
  ASSERT_TRUE(coverage.ok()) << out;
  EXPECT_EQ(coverage->at("lights_from").get<std::string>(), "capture guidance");
  EXPECT_GT(coverage->at("covered").get<int>(), 0);
  EXPECT_TRUE(fs::exists(dir / "s" / "rig_layout.json"));
  // The images the guidance counted are recorded for the reconstruction.
  auto manifest = ReadJsonFile(dir / "s" / "session.json");
  ASSERT_TRUE(manifest.ok());
  EXPECT_EQ(manifest->value("mirror_images", Json::array()), Json::array({"half_turn"})) << manifest->dump();
  // The virtual rig's truth of both runs, under the session's names: the checkerboard poses, and
  // each flash where it was (the guide's quick reading of the balls agrees with it).
  auto truth = ReadJsonFile(dir / "s" / "truth.json");
  ASSERT_TRUE(truth.ok()) << out;
  EXPECT_EQ(truth->at("calib_shots").size(), 10u);
  EXPECT_EQ(truth->at("calib_shots")[9].at("file").get<std::string>(), "calib/calib_0010.jpg");
  ASSERT_EQ(truth->at("shots").size(), 8u);
  std::map<std::string, Eigen::Vector3d> where;
  for (const Json& shot : truth->at("shots")) where[shot.at("file").get<std::string>()] = JsonVector3d(shot.at("light_m"), "light_m", 100);
  const Eigen::Vector3d top = JsonVector3d(truth->at("boards")[0].at("t"), "t", 100);
  int compared = 0;
  for (const Json& flash : coverage->at("flashes")) {
    const std::string file = flash.at("shot").get<std::string>();
    ASSERT_TRUE(where.count(file)) << file;
    const Eigen::Vector3d seen = JsonVector3d(flash.at("position_cam_m"), "position_cam_m", 100) - top;
    const double off_deg = std::acos(std::clamp(seen.normalized().dot((where[file] - top).normalized()), -1.0, 1.0)) * 180 / M_PI;
    std::printf("%s: the guide's flash %.2f deg from the truth's\n", file.c_str(), off_deg);
    EXPECT_LT(off_deg, 2.0) << file;
    ++compared;
  }
  EXPECT_EQ(compared, 8);
  // A truth.json that cannot be read is named and left as it was, not replaced by one run's shots.
  std::ofstream(dir / "s" / "truth.json") << "[1,2";
  ASSERT_EQ(testing::RunMesocap("capture --out " + session + camera + " --resume --shots 1 --no-progress", &out), 0) << out;
  EXPECT_NE(out.find("truth.json"), std::string::npos) << out;
  std::ifstream kept(dir / "s" / "truth.json");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(kept), {}), "[1,2");
}

}  // namespace
}  // namespace mesocap

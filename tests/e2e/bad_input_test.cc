// Bad input through the real CLI, command by command: a wrong path, an empty folder, a corrupt
// image, a truncated or crafted manifest. Each must end with one line naming the file, exit code
// 1 (2 for a bad option), never 70 or a signal, and no visible output left behind.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>

#include "core/image_io.h"
#include "formats/ptm_file.h"
#include "reconstruct/ptm.h"
#include "tests/testing.h"

namespace mesocap {
namespace {
namespace fs = std::filesystem;

struct Case {
  std::string args;       // "{d}" stands for the test folder
  int exit_code;
  std::string fragment;   // must appear in the last line (a file name, the reason)
};

void WriteText(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

std::string ReadBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// Every visible (not dot-named) path under `dir`.
std::set<std::string> VisibleEntries(const fs::path& dir) {
  std::set<std::string> names;
  for (auto it = fs::recursive_directory_iterator(dir); it != fs::recursive_directory_iterator(); ++it) {
    if (it->path().filename().string().rfind(".", 0) == 0) {
      if (it->is_directory()) it.disable_recursion_pending();
      continue;
    }
    names.insert(fs::relative(it->path(), dir).string());
  }
  return names;
}

std::string Replace(std::string s, const std::string& from, const std::string& to) {
  for (size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size())) s.replace(at, from.size(), to);
  return s;
}

std::string LastLine(const std::string& out) {
  std::string s = out;
  while (!s.empty() && s.back() == '\n') s.pop_back();
  return s.substr(s.rfind('\n') == std::string::npos ? 0 : s.rfind('\n') + 1);
}

// The inputs every case draws from.
void MakeInputs(const fs::path& d) {
  fs::create_directories(d / "empty");
  Image ramp(64, 48, 3);
  for (size_t i = 0; i < ramp.size(); ++i) ramp.data()[i] = float(i % 97) / 97.f;
  ASSERT_TRUE(WriteImage(d / "good.jpg", ramp).ok());
  const std::string jpeg = ReadBytes(d / "good.jpg");
  WriteText(d / "corrupt" / "garbage.jpg", "not an image\n");
  WriteText(d / "corrupt" / "cut.jpg", jpeg.substr(0, jpeg.size() / 3));
  // A 700-byte-class JPEG whose header declares 60000 x 60000.
  std::string huge = jpeg;
  const size_t sof = huge.find("\xFF\xC0");
  huge[sof + 5] = char(60000 >> 8), huge[sof + 6] = char(60000 & 255), huge[sof + 7] = huge[sof + 5], huge[sof + 8] = huge[sof + 6];
  WriteText(d / "huge" / "huge.jpg", huge);
  std::string lp = "6\n";
  for (int i = 0; i < 6; ++i) {  // a well-spread light set: two rings, three azimuths each
    const double r = i % 2 ? 0.8 : 0.4, a = i * M_PI / 3;
    lp += "huge.jpg " + std::to_string(r * std::cos(a)) + " " + std::to_string(r * std::sin(a)) + " " +
          std::to_string(std::sqrt(1 - r * r)) + "\n";
  }
  WriteText(d / "huge" / "huge.lp", lp);
  WriteText(d / "truncated.lp", "6\ngood.jpg 0.1 0.2 0.9\n");
  WriteText(d / "corrupt.lp", Replace(lp, "huge.jpg", "corrupt/cut.jpg"));
  // PTMs: truncated, and a crafted scale whose decoded range is not finite.
  Ptm ptm;
  ptm.coefficients = Image(4, 3, 6, 0.25f);
  ptm.rgb = Image(4, 3, 3, 0.5f);
  ASSERT_TRUE(WritePtmFile(d / "good.ptm", ptm).ok());
  const std::string ptm_bytes = ReadBytes(d / "good.ptm");
  WriteText(d / "truncated.ptm", ptm_bytes.substr(0, ptm_bytes.size() - 10));
  size_t line4 = 0;
  for (int i = 0; i < 4; ++i) line4 = ptm_bytes.find('\n', line4) + 1;
  std::string crafted = ptm_bytes;
  crafted.replace(line4, ptm_bytes.find('\n', line4) - line4, "1 1 3e38 1 1 1");
  fs::remove(d / "good.ptm");
  WriteText(d / "crafted.ptm", crafted);
  // Manifests: truncated session and index; a session that is not an object; an index with a
  // crafted angle; a layout with zero balls.
  WriteText(d / "truncated_session" / "session.json", "{\"format\": \"mesocap-ses");
  WriteText(d / "array_session" / "session.json", "[1, 2, 3]");
  WriteText(d / "zero_balls" / "session.json", "{\"format\": \"mesocap-session\"}");
  WriteText(d / "zero_balls" / "rig_layout.json",
            R"({"boards": [{"id": 0, "size_m": 0.1, "patch_m": 0.05, "tags": [{"id": 1, "size_m": 0.02,
                "corners_m": [[0,0],[0.02,0],[0.02,0.02],[0,0.02]]}]}], "spheres": {"count": 0, "radius_m": 0.03},
                "grey_cards": {"albedo": 0.18, "mounts": []}, "checkerboard": {"cols": 9, "rows": 6, "square_m": 0.02}})");
  WriteText(d / "index" / "truncated.json", "{\"format\": \"mesocap-btf\", \"slices\": [{\"file\": \"a.exr\"");
  WriteText(d / "index" / "theta.json", R"({"format": "mesocap-btf", "slices": [{"file": "a.exr", "theta_i_deg": 1e300,
              "phi_i_deg": 0, "theta_o_deg": 0, "phi_o_deg": 0}]})");
  WriteText(d / "index" / "escape.json", R"({"format": "mesocap-btf", "slices": [{"file": "../../etc/passwd",
              "theta_i_deg": 10, "phi_i_deg": 0, "theta_o_deg": 0, "phi_o_deg": 0}]})");
  WriteText(d / "full" / "x.txt", "already here");
}

const Case kCases[] = {
    {"simulate --out {d}/full --no-progress", 2, "full: exists and is not empty"},
    {"simulate --out {d}/new --material velvet --no-progress", 2, "velvet"},
    {"demo --out {d}/full --no-progress", 2, "full"},
    {"import {d}/nope --out {d}/new", 2, "nope"},
    {"import {d}/empty --out {d}/new", 1, "empty: no importable photo"},
    {"import {d}/corrupt --out {d}/new", 1, "skipped 2 files, first cut.jpg"},
    {"capture --out {d}/full --camera virtual --shots 1", 2, "full"},
    {"capture --out {d}/new --camera virtual --calibration --guide --shots 1", 2, "--guide follows flash shots"},
    {"capture --out {d}/new --camera fake --port {d}/corrupt --follow-guide --shots 1", 2, "--follow-guide needs a camera"},
    {"capture --out {d}/new --camera virtual --guide --guide-after 0 --shots 1", 2, "--guide-after"},
    {"calibrate-camera --images {d}/nope --board 9x6 --square 0.02 --out {d}/camera.json --no-progress", 2, "nope"},
    {"calibrate-camera --images {d}/empty --board 9x6 --square 0.02 --out {d}/camera.json --no-progress", 1, "empty"},
    {"calibrate-camera --images {d}/corrupt --board 9x6 --square 0.02 --out {d}/camera.json --no-progress", 1, "corrupt/"},
    {"calibrate {d}/nope --no-progress", 1, "nope: not a mesocap session"},
    {"calibrate {d}/truncated_session --no-progress", 1, "truncated_session/session.json: invalid JSON"},
    {"calibrate {d}/array_session --no-progress", 1, "array_session/session.json: must be a JSON object"},
    {"calibrate {d}/zero_balls --no-progress", 1, "rig_layout.json: rig layout: spheres.count = 0"},
    {"fit-ptm --lp {d}/nope.lp --out {d}/out.ptm --no-progress", 1, "nope.lp"},
    {"fit-ptm --lp {d}/truncated.lp --out {d}/out.ptm --no-progress", 1, "truncated.lp"},
    {"fit-ptm --lp {d}/corrupt.lp --out {d}/out.ptm --no-progress", 1, "cut.jpg"},
    {"fit-ptm --lp {d}/huge/huge.lp --out {d}/out.ptm --linearize --no-progress", 1, "huge.jpg: the image declares 60000x60000"},
    {"fit-ptm --lp {d}/huge/huge.lp --out {d}/out.ptm --no-progress", 1, "huge.jpg: the image declares 60000x60000"},
    {"relight {d}/nope.ptm --light 0,0,1 --out {d}/relit.png", 1, "nope.ptm"},
    {"relight {d}/truncated.ptm --light 0,0,1 --out {d}/relit.png", 1, "truncated.ptm: truncated PTM file"},
    {"relight {d}/crafted.ptm --light 0,0,1 --out {d}/relit.png", 1, "crafted.ptm: malformed PTM header: scale 2"},
    {"reconstruct {d}/nope --out {d}/btf --no-progress", 1, "nope/slices/index.json"},
    {"reconstruct --slices {d}/index/truncated.json --out {d}/btf --no-progress", 1, "truncated.json: invalid JSON"},
    {"reconstruct --slices {d}/index/theta.json --out {d}/btf --no-progress", 1, "theta_i_deg = 1e+300 is outside [0, 90]"},
    {"reconstruct --slices {d}/index/escape.json --out {d}/btf --no-progress", 1, "must not leave its folder"},
    {"reconstruct --slices {d}/index/theta.json --pair 45x90x60x10abc --out {d}/btf", 2, "45x90x60x10abc"},
    {"reconstruct --slices {d}/index/theta.json --pair 45,90,60,0,77 --out {d}/btf", 2, "45,90,60,0,77"},
    {"reconstruct --slices {d}/index/theta.json --pair 45,pi-30.0,60,0 --out {d}/btf", 2, "pi-30.0"},
    {"reconstruct --slices {d}/index/theta.json --pair 45,10.01,60,0 --pair 45,10.04,60,0 --out {d}/btf", 2,
     "both name slices/ti45.0_pi010.0_to60.0_po000.0.exr"},
    {"evaluate --out {d}/full --no-progress", 2, "full"},
    {"evaluate --out {d}/eval --colour-space hsv --no-progress", 2, "hsv"},
    {"evaluate --out {d}/eval --pairs 0 --no-progress", 2, "--pairs must be a positive count"},
    {"evaluate --session {d}/nope --out {d}/eval --no-progress", 2, "nope/truth.json not found"},
    {"evaluate --session {d}/nope --material stones --out {d}/eval --no-progress", 2, "--material excludes --session"},
    {"coverage {d}/nope", 1, "nope/calibration/rig.json"},
    {"coverage {d}/nope --near-deg 0", 2, "--near-deg"},
    {"reconstruct --slices {d}/index/theta.json --colour-space lab --out {d}/btf", 2, "lab"},
    {"lights --images {d}/nope --sphere 10,10,5", 2, "nope"},
    {"lights --images {d}/empty --sphere 10,10,5", 1, "empty"},
    {"synth --input {d}/nope --out {d}/synth --no-progress", 1, "nope: no such file or folder"},
    {"synth --input {d}/empty --out {d}/synth --no-progress", 1, "empty"},
    {"synth --input {d}/corrupt/garbage.jpg --out {d}/synth --no-progress", 1, "garbage.jpg"},
    {"synth --input {d}/index/truncated.json --out {d}/synth --no-progress", 1, "truncated.json: invalid JSON"},
    {"synth --input {d}/crafted.ptm --out {d}/synth --no-progress", 1, "crafted.ptm"},
    {"synth --input {d}/huge/huge.jpg --out {d}/synth --no-progress", 1, "huge.jpg: the image declares 60000x60000"},
    {"synth-apply --map {d}/nope.exr --input {d}/good.jpg --out {d}/applied --no-progress", 1, "nope.exr"},
    {"synth-apply --map {d}/corrupt/cut.jpg --input {d}/good.jpg --out {d}/applied --no-progress", 1, "cut.jpg"},
    {"paint --input {d}/nope --feature-mask {d}/good.jpg --target-mask {d}/good.jpg --out {d}/painted --no-progress", 1, "nope"},
    {"paint --input {d}/good.jpg --feature-mask {d}/corrupt/cut.jpg --target-mask {d}/good.jpg --out {d}/painted --no-progress", 1, "cut.jpg"},
    {"fit-ptm --lp {d}/truncated.lp --out {d}/out.ptm --no-such-option", 2, "--no-such-option"},
};

TEST(BadInput, EveryCommandFailsWithOneLineNamingTheFileAndLeavesNothing) {
  const fs::path d = testing::MakeTempDir();
  MakeInputs(d);
  const std::set<std::string> before = VisibleEntries(d);
  for (const Case& c : kCases) {
    std::string out;
    const int code = testing::RunMesocap(Replace(c.args, "{d}", d.string()), &out);
    const std::string last = LastLine(out);
    EXPECT_EQ(code, c.exit_code) << c.args << "\n" << out;
    EXPECT_NE(last.find(c.fragment), std::string::npos) << c.args << "\n" << out;
    EXPECT_EQ(last.rfind("mesocap", 0), 0u) << c.args << "\n" << out;
    EXPECT_EQ(VisibleEntries(d), before) << c.args << " left output behind";
  }
}

}  // namespace
}  // namespace mesocap

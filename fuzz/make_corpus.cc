// Writes the seed corpora fuzz/corpus/<target>/ with the project's own writers (WritePtmFile,
// WriteLpFile, WriteImage, Session, RigLayout and CameraModel ToJson) plus a few hand-written
// variants a lab's files may have (CRLF, Windows paths, wrapped camera files). Every seed is a
// few KB at most. Usage: make_corpus OUT_DIR [rig_layout.json of a simulated session]
// (scripts/fuzz.sh --make-corpus). The slice indexes name the files fuzz/slice_files.h provides.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "calib/calibrate.h"
#include "core/atomic_file.h"
#include "core/camera_model.h"
#include "core/image_io.h"
#include "core/json.h"
#include "core/rig_layout.h"
#include "core/session.h"
#include "core/stage_cache.h"
#include "formats/lp_file.h"
#include "mesh/mesh_shapes.h"
#include "mesh/surface_map_file.h"
#include "mesh/tangent_frames.h"
#include "synth/synth_map.h"
#include "synth/texton_analysis.h"
#include "formats/ptm_file.h"
#include "fuzz/fuzz_support.h"

namespace fs = std::filesystem;
using namespace mesocap;

namespace {

void Check(const Status& st) {
  if (!st.ok()) {
    std::fprintf(stderr, "make_corpus: %s\n", st.message().c_str());
    std::exit(1);
  }
}

Image Pattern(int w, int h, int channels, int seed) {
  Image image(w, h, channels);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < channels; ++c)
        image.at(x, y, c) = 0.5f + 0.45f * std::sin(0.9f * x + 0.5f * y * (seed + 1) + 2.0f * c);
  return image;
}

Ptm MakePtm(PtmFormat format, int w, int h) {
  Ptm ptm;
  ptm.format = format;
  const int n = format == PtmFormat::kLrgb ? 6 : 18;
  ptm.coefficients = Image(w, h, n);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < n; ++k) ptm.coefficients.at(x, y, k) = 0.3f * std::sin(float(x + 2 * y + k)) + (k % 6 == 5 ? 0.5f : 0.f);
  if (format == PtmFormat::kLrgb) ptm.rgb = Pattern(w, h, 3, 1);
  return ptm;
}

void Ptms(const fs::path& dir) {
  PtmWriteOptions integer, floats;
  floats.integer_scales = false;
  Check(WritePtmFile(dir / "lrgb_4x3.ptm", MakePtm(PtmFormat::kLrgb, 4, 3), integer));
  Check(WritePtmFile(dir / "rgb_3x2.ptm", MakePtm(PtmFormat::kRgb, 3, 2), integer));
  Check(WritePtmFile(dir / "lrgb_2x2_float_scales.ptm", MakePtm(PtmFormat::kLrgb, 2, 2), floats));
  Check(WritePtmFile(dir / "rgb_1x1_float_scales.ptm", MakePtm(PtmFormat::kRgb, 1, 1), floats));
}

void Lps(const fs::path& dir) {
  // Names match the files fuzz_lp_file.cc puts beside the .lp file.
  const fs::path folder = "/nonexistent-rti";
  Check(WriteLpFile(dir / "written.lp", {{folder / "img_01.jpg", {0.1, 0.2, 0.97}},
                                         {folder / "img_02.jpg", {-0.5, 0.1, 0.86}},
                                         {folder / "img 03.png", {0.0, -0.6, 0.8}}}));
  fuzz::WriteText(dir / "crlf_windows_paths.lp",
                  "3\r\nC:\\rti\\img_01.jpg 0.1 0.2 0.97\r\nphotos\\img_04.tif -0.5 0.1 0.86\r\n"
                  "D:\\other\\img_02.jpg 0 -0.6 0.8\r\n");
  fuzz::WriteText(dir / "spaces_exponents.lp",
                  "  2  \n\n img 03.png\t1e-1 -2.5E-1 9.6e-01 \nphotos/img_04.tif 0 0 1\n");
  fuzz::WriteText(dir / "relative_absolute.lp", "2\n./img_01.jpg 0.3 0.3 0.9\n/tmp/img_02.jpg 0.2 0.1 0.97\n");
}

void Sessions(const fs::path& manifest_dir, const fs::path& journal_dir) {
  const fs::path tmp = fuzz::ScratchDir() / "session";
  Json manifest = {{"source", "virtual"}, {"camera", {{"model", "virtual rig"}, {"port", "virtual:seed=1"}}},
                   {"material", "weave"},
                   {"provenance", {{"program", "mesocap"}, {"version", "0.1.0"}, {"command_line", "mesocap simulate"},
                                   {"time_utc", "2026-01-01T12:00:00Z"}, {"options", {{"shots", 2}}}}}};
  auto session = Session::Create(tmp, manifest);
  Check(session.status());
  for (int i = 1; i <= 3; ++i) {
    ShotRecord r;
    r.index = i;
    r.kind = i == 3 ? "calib" : "shot";
    r.file = SessionLayout::ShotEntry(r.kind, i, ".jpg");
    r.time_utc = "2026-01-01T12:00:0" + std::to_string(i) + "Z";
    r.settings = {{"iso", 100}, {"shutterspeed", "1/125"}, {"f-number", "f/8"}, {"flash", true}};
    r.exif = {{"ExposureTime", 0.008}, {"FNumber", 8.0}, {"ISO", 100}, {"Flash", i == 2 ? 0 : 1}};
    if (i == 2) r.flags = {"flash_not_fired"};
    Check(session->RecordShot(r));
  }
  Check(session->UpdateManifest({{"calibration", {{"done", true}}}}));
  fs::copy_file(SessionLayout(tmp).manifest(), manifest_dir / "session.json", fs::copy_options::overwrite_existing);
  fs::copy_file(SessionLayout(tmp).journal(), journal_dir / "journal.jsonl", fs::copy_options::overwrite_existing);
  fuzz::WriteText(manifest_dir / "minimal.json", "{\"format\":\"mesocap-session\",\"format_version\":1}\n");
  // A torn last line (a crash while appending) and a non-shot event.
  fuzz::WriteText(journal_dir / "torn.jsonl",
                  "{\"index\":7,\"kind\":\"shot\",\"file\":\"shots/shot_0007.jpg\",\"event\":\"shot\"}\n"
                  "{\"event\":\"resume\",\"time_utc\":\"2026-01-01T12:01:00Z\"}\n"
                  "{\"index\":8,\"kind\":\"calib\",\"file\":\"calib/calib_0008.jpg\",\"flags\":[\"x\"],\"ev");
}

void Layouts(const fs::path& dir, const fs::path& simulated) {
  RigLayout l;
  for (int b = 0; b < 2; ++b) {
    LayoutBoard board;
    board.id = b;
    board.size_m = 0.1;
    board.patch_m = 0.05;
    board.nominal_incidence_deg = b == 0 ? 0 : 30;
    for (int t = 0; t < 2; ++t) {
      LayoutTag tag;
      tag.id = 10 * b + t;
      tag.size_m = 0.012;
      const double x0 = t == 0 ? -0.045 : 0.033, y0 = -0.045;
      tag.corners_m = {Eigen::Vector2d(x0, y0), Eigen::Vector2d(x0 + 0.012, y0), Eigen::Vector2d(x0 + 0.012, y0 + 0.012),
                       Eigen::Vector2d(x0, y0 + 0.012)};
      board.tags.push_back(tag);
    }
    l.boards.push_back(board);
  }
  l.sphere_count = 4;
  l.sphere_radius_m = 0.0286;
  LayoutBoard card = l.boards[0];
  card.id = 100;
  l.grey_cards = {card};
  l.grey_card_albedo = 0.18;
  l.checker_cols = 9, l.checker_rows = 6, l.checker_square_m = 0.035;
  fuzz::WriteText(dir / "two_boards.json", l.ToJson().dump() + "\n");
  if (!simulated.empty()) {  // the virtual rig's full layout, compact
    auto j = ReadJsonFile(simulated);
    Check(j.status());
    fuzz::WriteText(dir / "virtual_rig.json", j->dump() + "\n");
  }
}

void Cameras(const fs::path& dir) {
  CameraModel c;
  c.width = 3000, c.height = 2000;
  c.K << 6000, 0, 1499.5, 0, 6000, 999.5, 0, 0, 1;
  c.dist = {-0.08, 0.12, 0.0004, -0.0003, -0.02};
  fuzz::WriteText(dir / "camera.json", c.ToJson().dump(2) + "\n");
  Json wrapped = {{"camera", c.ToJson()}, {"report", {{"images_used", 14}, {"rms_reprojection_px", 0.21}}}};
  fuzz::WriteText(dir / "calibrate_camera_out.json", wrapped.dump() + "\n");
}

// calibration/rig.json as calibrate writes it: two boards (one not found), two shots (one with
// its flash found); stages.json as process writes it; a hand-marked corners file.
void SessionRecords(const fs::path& rig_dir, const fs::path& stages_dir, const fs::path& marked_dir) {
  CalibrationResult rig;
  rig.camera.width = 1500, rig.camera.height = 1000;
  rig.camera.K << 3000, 0, 749.5, 0, 3000, 499.5, 0, 0, 1;
  rig.camera.dist = {-0.08, 0.12, 0.0004, -0.0003, -0.02};
  BoardPose top;
  top.id = 0, top.found = true, top.t = {0.01, -0.02, 0.6}, top.corners_used = 48, top.shots_seen = 12;
  top.rms_reprojection_px = 0.4;
  BoardPose hidden;
  hidden.id = 1, hidden.why_not = "tags never detected (hidden or unlit)";
  rig.boards = {top, hidden};
  ShotCalibration lit;
  lit.file = "shots/shot_0001.jpg", lit.light.ok = true, lit.light.light_m = {0.3, 0.2, 0.5}, lit.power = 1;
  lit.light.highlights_used = 3;
  ShotCalibration dark;
  dark.file = "shots/shot_0002.jpg", dark.light.flag = "no highlight", dark.flag = "flash not found";
  rig.shots = {lit, dark};
  Check(WriteJsonFile(rig_dir / "rig.json", rig.RigJson()));

  StageCache cache = *StageCache::Open(stages_dir);
  StageRecord calibrate;
  calibrate.inputs_hash = "00112233445566778899aabbccddeeff", calibrate.version = 1, calibrate.seconds = 2.5;
  calibrate.finished_utc = "2026-12-06T10:00:00Z", calibrate.summary = {{"brief", "2 boards"}, {"warnings", {"w"}}};
  StageRecord synth = calibrate;
  synth.read["calibrate"] = "ffeeddccbbaa99887766554433221100";
  Check(cache.Record("calibrate", calibrate));
  Check(cache.Record("synth", synth));  // no outputs: hashes of nothing

  const Json marked = {{"format", "mesocap-marked-corners"},
                       {"shots", {{{"file", "shots/shot_0001.jpg"},
                                   {"boards", {{{"id", 1}, {"corners_px", {{100, 120}, {300, 118}, {302, 320}, {98, 322}}}}}}}}}};
  fuzz::WriteText(marked_dir / "marked.json", marked.dump(2) + "\n");
}

Json SliceEntry(const std::string& file, int board, double ti, double pi, double to, double po) {
  return {{"file", file}, {"board", board}, {"shot", "shots/shot_0001.jpg"}, {"theta_i_deg", ti}, {"phi_i_deg", pi},
          {"theta_o_deg", to}, {"phi_o_deg", po}, {"light_distance_m", 1.0}, {"scale", 1.0}};
}

void SliceIndexes(const fs::path& slice_dir, const fs::path& btf_dir) {
  // A session's slices/index.json: two boards, the top one with four lights, one with three.
  Json slices = Json::array();
  const double lights[4][2] = {{20, 0}, {45, 90}, {60, 200}, {35, 300}};
  for (int k = 0; k < 4; ++k)
    slices.push_back(SliceEntry("board_00/shot_000" + std::to_string(k + 1) + ".exr", 0, lights[k][0], lights[k][1], 0.5, 270));
  for (int k = 0; k < 3; ++k)
    slices.push_back(SliceEntry("board_01/shot_000" + std::to_string(k + 1) + ".exr", 1, lights[k][0], lights[k][1] + 10, 30, 90));
  Json session_index = {{"format", "mesocap-slices"}, {"format_version", 1}, {"size", 16}, {"slices", slices},
                        {"skipped", Json::array({{{"board", 1}, {"shot", "shots/shot_0004.jpg"}, {"reason", "light behind the board"}}})}};
  fuzz::WriteText(slice_dir / "two_boards.json", session_index.dump() + "\n");
  fuzz::WriteText(btf_dir / "session_slices.json", session_index.dump() + "\n");
  // Odd cases: a bare list, files of other sizes and channel counts, a corrupt file.
  Json odd = Json::array({SliceEntry("board_00/shot_0001.exr", 0, 10, 0, 0, 0), SliceEntry("big/shot_0001.exr", 0, 40, 90, 0, 0),
                          SliceEntry("grey/shot_0001.png", 0, 50, 180, 0, 0), SliceEntry("rgba/shot_0001.png", 0, 60, 270, 0, 0),
                          SliceEntry("odd/shot_0001.exr", 2, 30, 0, 60, 0), SliceEntry("bad/shot_0001.exr", 2, 30, 90, 60, 0)});
  fuzz::WriteText(slice_dir / "odd_files_list.json", odd.dump() + "\n");
  // The top board's slices with one grey and one RGBA file among them (channel counts differ).
  Json channels = Json::array();
  for (int k = 0; k < 3; ++k)
    channels.push_back(SliceEntry("board_00/shot_000" + std::to_string(k + 1) + ".exr", 0, lights[k][0], lights[k][1], 0, 0));
  channels.push_back(SliceEntry("grey/shot_0001.png", 0, 70, 45, 0, 0));
  channels.push_back(SliceEntry("rgba/shot_0001.png", 0, 80, 135, 0, 0));
  fuzz::WriteText(slice_dir / "mixed_channels.json", Json{{"slices", channels}}.dump() + "\n");
  // A reconstructed BTF's index.json (format mesocap-btf): one view, four lights.
  Json btf_slices = Json::array();
  for (int k = 0; k < 4; ++k)
    btf_slices.push_back({{"file", "board_00/shot_000" + std::to_string(k + 1) + ".exr"}, {"theta_i_deg", lights[k][0]},
                          {"phi_i_deg", lights[k][1]}, {"theta_o_deg", 0.0}, {"phi_o_deg", 0.0}});
  Json btf = {{"format", "mesocap-btf"}, {"width", 16}, {"height", 16}, {"views_measured", 1}, {"top_board", 0},
              {"slices", btf_slices}};
  fuzz::WriteText(btf_dir / "reconstructed.json", btf.dump() + "\n");
  Json btf_odd = btf;
  btf_odd["slices"].push_back({{"file", "big/shot_0001.exr"}, {"theta_i_deg", 70}, {"phi_i_deg", 45},
                               {"theta_o_deg", 10}, {"phi_o_deg", 0}});
  btf_odd["slices"].push_back({{"file", "grey/shot_0001.png"}, {"theta_i_deg", 80}, {"phi_i_deg", 45},
                               {"theta_o_deg", 10}, {"phi_o_deg", 0}});
  fuzz::WriteText(btf_dir / "mixed_sizes.json", btf_odd.dump() + "\n");
  fuzz::WriteText(slice_dir / "reconstructed_format.json", btf.dump() + "\n");
}

void Images(const fs::path& all, const fs::path& u8) {
  auto write = [](const fs::path& path, const Image& image, PixelFormat format, ImageAttributes attributes = {}) {
    ImageWriteOptions o;
    o.format = format;
    o.attributes = std::move(attributes);
    o.jpeg_quality = 80;
    Check(WriteImage(path, image, o));
  };
  const ImageAttributes exif = {{"Make", std::string("mesocap")}, {"Model", std::string("virtual rig")},
                                {"ExposureTime", 0.008f}, {"Exif:Flash", 1},
                                {"Exif:DateTimeOriginal", std::string("2026:01:01 12:00:00")}};
  write(all / "rgb_16x12_exif.jpg", Pattern(16, 12, 3, 0), PixelFormat::kUint8Srgb, exif);
  write(all / "grey_9x7.jpg", Pattern(9, 7, 1, 1), PixelFormat::kUint8Srgb);
  write(all / "rgba_8x8_8bit.png", Pattern(8, 8, 4, 2), PixelFormat::kUint8Srgb);
  write(all / "rgb_8x6_16bit.png", Pattern(8, 6, 3, 3), PixelFormat::kUint16Linear);
  write(all / "rgb_8x8_16bit.tif", Pattern(8, 8, 3, 4), PixelFormat::kUint16Linear);
  write(all / "rgb_8x8_half.exr", Pattern(8, 8, 3, 5), PixelFormat::kHalf,
        {{"mesocap:theta_i_deg", 45.0f}, {"mesocap:board", 1}, {"mesocap:material", std::string("weave")}});
  write(all / "grey_4x4_float.exr", Pattern(4, 4, 1, 6), PixelFormat::kFloat);
  write(all / "rgb_6x4.hdr", Pattern(6, 4, 3, 7), PixelFormat::kFloat);
  write(u8 / "rgb_16x12_exif.jpg", Pattern(16, 12, 3, 0), PixelFormat::kUint8Srgb, exif);
  write(u8 / "rgb_17x9.jpg", Pattern(17, 9, 3, 8), PixelFormat::kUint8Srgb);
  write(u8 / "grey_9x7.jpg", Pattern(9, 7, 1, 1), PixelFormat::kUint8Srgb);
  write(u8 / "rgb_8x8_8bit.png", Pattern(8, 8, 3, 9), PixelFormat::kUint8Srgb);
}

// A map and a two-level texton analysis, as synth writes them beside its outputs.
void SynthFiles(const fs::path& dir) {
  SynthMap map(8, 6, 16, 16, "texton");
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x) map.Set(x, y, float(x + 2) + 0.5f, float(y) + 0.5f, 0.f, y / 3);
  Check(WriteSynthMap(dir / "map.exr", map));
  TextonAnalysis analysis;
  analysis.slice_count = 3;
  analysis.representative_slices = {0, 2};
  for (int l = 0; l < 2; ++l) {
    TextonLevel level;
    level.width = level.height = 8;  // a Gaussian stack: every level at the sample's size
    level.spacing = 1 << l;
    level.textons = 4 >> l;
    for (int t = 0; t < level.width * level.height; ++t) level.labels.push_back(t % level.textons);
    level.gamma = Eigen::MatrixXd::Identity(level.textons + 1, level.textons + 1);
    analysis.levels.push_back(level);
  }
  Check(WriteTextonAnalysis(dir / "textons.exr", analysis));
}

// A dressed icosahedron (a sample coordinate per vertex; and with an atlas, as quilts carry) and a
// two-point direction field.
void MeshFiles(const fs::path& dir) {
  DressedMesh d;
  d.mesh = IcoSphere(1);
  d.frames = RelaxedFrames(d.mesh);
  d.map.method = "texton", d.map.sample_width = d.map.sample_height = 16, d.map.texel_size = 0.3;
  for (int v = 0; v < d.mesh.vertex_count(); ++v)
    d.map.source_x.push_back(float(v % 16) + 0.5f), d.map.source_y.push_back(float(v / 16) + 0.5f), d.map.label.push_back(v % 5);
  Check(WriteDressedMesh(dir / "surface_map.ply", d));
  // A quilt's: the same with an atlas (per-face texture coordinates).
  auto atlas = BuildAtlas(d.mesh, {64, 2});
  Check(atlas.status());
  d.map.method = "quilt", d.atlas = *atlas;
  Check(WriteDressedMesh(dir / "surface_map_quilt.ply", d));
  Check(WriteTextAtomically(dir / "field.json",
                            "{\"points\": [[1, 0, 0], [0, 0, 1]], \"directions\": [[0, 1, 0], [1, 0, 0]]}\n"));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: make_corpus OUT_DIR [simulated rig_layout.json]\n");
    return 2;
  }
  const fs::path out = argv[1];
  const fs::path simulated = argc > 2 ? argv[2] : "";
  auto dir = [&](const char* name) {
    fs::create_directories(out / name);
    return out / name;
  };
  Ptms(dir("ptm_file"));
  Lps(dir("lp_file"));
  Sessions(dir("session_json"), dir("journal_jsonl"));
  Layouts(dir("rig_layout"), simulated);
  Cameras(dir("camera_json"));
  SliceIndexes(dir("slice_index"), dir("btf_index"));
  fs::copy(out / "slice_index", dir("slice_set"), fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  Images(dir("image"), dir("image_u8"));
  SynthFiles(dir("synth_files"));
  SessionRecords(dir("rig_json"), dir("stages_json"), dir("marked_corners"));
  MeshFiles(dir("mesh_files"));
  return 0;
}

#include "core/session_layout.h"

#include <cstdio>

namespace mesocap {
namespace fs = std::filesystem;

namespace {

// `n` in `width` digits, or `placeholder` for kPattern (the name's pattern, for `mesocap layout`).
std::string Numbered(int n, int width, const char* placeholder) {
  if (n == kPattern) return placeholder;
  char digits[16];
  std::snprintf(digits, sizeof digits, "%0*d", width, n);
  return digits;
}

std::string BoardName(int board) { return "board_" + Numbered(board, 2, "BB"); }

// Names shared by several folders.
constexpr const char* kIndex = "index.json";
constexpr const char* kReport = "report.json";
constexpr const char* kSlices = "slices";
constexpr const char* kBtf = "btf";
constexpr const char* kShots = "shots";
constexpr const char* kCalib = "calib";  // the checkerboard shots' folder and kind

const char* ShotFolder(const std::string& kind) { return kind == kCalib ? kCalib : kShots; }

}  // namespace

fs::path BtfFolder::index() const { return root / kIndex; }
fs::path BtfFolder::slices() const { return root / kSlices; }
std::string BtfFolder::SliceEntry(const std::string& name) { return std::string(kSlices) + "/" + name; }

fs::path CalibrationFolder::rig() const { return root / "rig.json"; }
fs::path CalibrationFolder::report() const { return root / kReport; }
fs::path CalibrationFolder::lights_plot() const { return root / "lights.png"; }
fs::path CalibrationFolder::intrinsics_plot() const { return root / "intrinsics_residuals.png"; }
fs::path CalibrationFolder::flash_positions_plot() const { return root / "flash_positions.png"; }

fs::path SlicesFolder::index() const { return root / kIndex; }
fs::path SlicesFolder::board_lights(int board) const { return root / (BoardName(board) + ".lp"); }
std::string SlicesFolder::SliceEntry(int board, const std::string& shot_stem) {
  return BoardName(board) + "/" + shot_stem + ".exr";
}

fs::path PtmFolder::board_ptm(int board) const { return root / (BoardName(board) + ".ptm"); }
fs::path PtmFolder::board_residual(int board, const std::string& extension) const {
  return root / (BoardName(board) + "_residual" + extension);
}
fs::path PtmFolder::report() const { return root / kReport; }

fs::path SynthFolder::map() const { return root / "map.exr"; }
fs::path SynthFolder::patches() const { return root / "patches.png"; }
fs::path SynthFolder::image() const { return root / "synth.exr"; }
fs::path SynthFolder::ptm() const { return root / "synth.ptm"; }
fs::path SynthFolder::preview() const { return root / "preview.png"; }
fs::path SynthFolder::preview_light(int k) const { return root / ("preview_light" + Numbered(k, 1, "K") + ".png"); }
fs::path SynthFolder::textons() const { return root / "textons.exr"; }
fs::path SynthFolder::report() const { return root / kReport; }

fs::path DecorateFolder::surface_map() const { return root / "surface_map.ply"; }
fs::path DecorateFolder::textons() const { return root / "textons.exr"; }
fs::path DecorateFolder::atlas_map() const { return root / "atlas_map.exr"; }
fs::path DecorateFolder::report() const { return root / kReport; }
fs::path DecorateFolder::previews() const { return root / "previews"; }
fs::path DecorateFolder::sweep_frame(int k) const { return previews() / ("sweep_" + Numbered(k, 2, "KK") + ".png"); }
GltfFolder DecorateFolder::gltf() const { return {root / "gltf"}; }
fs::path DecorateFolder::preview_light(int k) const { return previews() / ("light_" + std::to_string(k) + ".png"); }

std::string GltfFolder::material_name() { return "material.gltf"; }
std::string GltfFolder::buffer_name() { return "material.bin"; }
std::string GltfFolder::base_color_name() { return "base_color.png"; }
std::string GltfFolder::metallic_roughness_name() { return "metallic_roughness.png"; }
std::string GltfFolder::normal_name() { return "normal.png"; }
fs::path GltfFolder::fit_report() const { return root / "fit.json"; }
fs::path GltfFolder::fit_error(const std::string& extension) const { return root / ("fit_error" + extension); }

fs::path PreviewsFolder::ptm_relit() const { return root / "ptm_relit.jpg"; }
fs::path PreviewsFolder::btf_slices() const { return root / "btf_slices.jpg"; }
fs::path PreviewsFolder::material_sphere() const { return root / "material_sphere.jpg"; }
fs::path PreviewsFolder::material_cloth() const { return root / "material_cloth.jpg"; }
fs::path PreviewsFolder::viewer() const { return root / "viewer.html"; }

fs::path ExportFolder::material_ptm() const { return root / "material.ptm"; }
fs::path ExportFolder::lp() const { return root / "lp"; }
fs::path ExportFolder::lp_file() const { return lp() / "material.lp"; }
fs::path ExportFolder::lp_slice(int k) const { return lp() / ("slice_" + Numbered(k, 4, "KKKK") + ".png"); }
BtfFolder ExportFolder::btf() const { return {root / kBtf}; }
fs::path ExportFolder::btf_multipart() const { return root / "btf.exr"; }
GltfFolder ExportFolder::gltf() const { return {root / "gltf"}; }
GltfFolder ExportFolder::gltf_synth() const { return {root / "gltf_synth"}; }
PreviewsFolder ExportFolder::previews() const { return {root / "previews"}; }

fs::path CoverageFolder::assessment() const { return root / "coverage.json"; }
fs::path CoverageFolder::plot() const { return root / "coverage.png"; }

fs::path ShardsFolder::shared() const { return root / "shared"; }
std::string ShardsFolder::statistics_name() { return "statistics.bin"; }
fs::path ShardsFolder::shared_lock() const { return root / "shared.lock"; }
fs::path ShardsFolder::part(int index, int count) const {
  return root / ("part_" + Numbered(index, 3, "III") + "_of_" + Numbered(count, 3, "NNN"));
}
fs::path ShardsFolder::part_lock(int index, int count) const {
  return root / (part(index, count).filename().string() + ".lock");
}
std::string ShardsFolder::part_record_name() { return "part.json"; }

fs::path SessionLayout::manifest() const { return root_ / "session.json"; }
fs::path SessionLayout::journal() const { return root_ / "journal.jsonl"; }
fs::path SessionLayout::shots() const { return root_ / kShots; }
fs::path SessionLayout::calib() const { return root_ / kCalib; }
fs::path SessionLayout::shots_of_kind(const std::string& kind) const { return root_ / ShotFolder(kind); }
std::string SessionLayout::ShotStem(const std::string& kind, int index) { return kind + "_" + Numbered(index, 4, "NNNN"); }
int SessionLayout::ShotIndexOf(const std::string& kind, const std::string& file_name) {
  const std::string prefix = kind + "_";
  if (file_name.rfind(prefix, 0) != 0) return 0;
  const size_t dot = file_name.find('.', prefix.size());
  if (dot == std::string::npos || dot + 1 == file_name.size()) return 0;  // an extension follows
  const std::string digits = file_name.substr(prefix.size(), dot - prefix.size());
  if (digits.empty() || digits.size() > 6 || digits.find_first_not_of("0123456789") != std::string::npos) return 0;
  return std::stoi(digits);
}
std::string SessionLayout::ShotEntry(const std::string& kind, int index, const std::string& extension) {
  return std::string(ShotFolder(kind)) + "/" + ShotStem(kind, index) + extension;
}
fs::path SessionLayout::truth() const { return root_ / "truth.json"; }
fs::path SessionLayout::rig_layout() const { return root_ / "rig_layout.json"; }
fs::path SessionLayout::simulate_report() const { return root_ / "simulate_report.json"; }
fs::path SessionLayout::import_report() const { return root_ / "import_report.json"; }
fs::path SessionLayout::capture_report() const { return root_ / "capture_report.json"; }
fs::path SessionLayout::lock() const { return root_ / ".mesocap.lock"; }
fs::path SessionLayout::stage_cache() const { return root_ / "stages.json"; }

CalibrationFolder SessionLayout::calibration() const { return {root_ / "calibration"}; }
SlicesFolder SessionLayout::slices() const { return {root_ / kSlices}; }
PtmFolder SessionLayout::ptm() const { return {root_ / "ptm"}; }
BtfFolder SessionLayout::btf() const { return {root_ / kBtf}; }
SynthFolder SessionLayout::synth() const { return {root_ / "synth"}; }
fs::path SessionLayout::decorate_root() const { return root_ / "decorate"; }
DecorateFolder SessionLayout::decorate(const std::string& mesh_name) const { return {decorate_root() / mesh_name}; }
ExportFolder SessionLayout::exports() const { return {root_ / "export"}; }
CoverageFolder SessionLayout::coverage() const { return {root_ / "coverage"}; }
fs::path SessionLayout::shards_root() const { return root_ / "shards"; }
ShardsFolder SessionLayout::shards(const std::string& stage, const std::string& key) const {
  return {shards_root() / (stage.empty() ? "STAGE" : stage) / (key.empty() ? "KEY" : key)};
}
fs::path SessionLayout::workflow() const { return root_ / "workflow"; }
fs::path SessionLayout::console() const { return root_ / "console"; }
fs::path SessionLayout::console_thumbnail(const std::string& shot_file) const {
  return console() / "thumbs" / (fs::path(shot_file).stem().string() + ".jpg");
}
fs::path SessionLayout::console_view(const std::string& shot_file) const {
  return console() / "views" / (fs::path(shot_file).stem().string() + ".jpg");
}
fs::path SessionLayout::console_process_log() const { return console() / "process.log"; }
fs::path SessionLayout::workflow_marker(const std::string& job) const {
  return workflow() / ((job.empty() ? "JOB" : job) + ".done");
}
fs::path SessionLayout::workflow_log(const std::string& job) const {
  return workflow() / ((job.empty() ? "JOB" : job) + ".log");
}

std::string ReportHtmlName() { return "report.html"; }
std::string ReportMarkdownName() { return "report.md"; }
fs::path SessionLayout::report_html() const { return root_ / ReportHtmlName(); }
fs::path SessionLayout::report_md() const { return root_ / ReportMarkdownName(); }
fs::path SessionLayout::report_files() const { return root_ / "report_files"; }
fs::path SessionLayout::light_coverage_plot() const { return report_files() / "light_coverage.png"; }

std::string RelativePath(const fs::path& path, const fs::path& base) {
  return path.lexically_relative(base).generic_string();
}

std::string SessionLayout::Relative(const fs::path& path) const { return RelativePath(path, root_); }

Json SessionLayout::ToJson() const {
  const auto rel = [&](const fs::path& p) { return Relative(p); };
  const CalibrationFolder c = calibration();
  const SlicesFolder s = slices();
  const PtmFolder p = ptm();
  const SynthFolder y = synth();
  const ExportFolder e = exports();
  const PreviewsFolder v = e.previews();
  const auto gltf = [&](const GltfFolder& g, bool fitted) {
    Json j = {{"folder", rel(g.root)},
              {"material", rel(g.material())},
              {"buffer", rel(g.buffer())},
              {"base_color", rel(g.base_color())},
              {"metallic_roughness", rel(g.metallic_roughness())},
              {"normal", rel(g.normal())}};
    if (fitted)  // the fit's record and error map: the material fitted to the BTF, not the one a map carries
      j.update({{"fit_report", rel(g.fit_report())},
                {"fit_error_png", rel(g.fit_error(".png"))},
                {"fit_error_exr", rel(g.fit_error(".exr"))}});
    return j;
  };
  const auto btf_folder = [&](const BtfFolder& b) {
    return Json{{"folder", rel(b.root)}, {"index", rel(b.index())}, {"slices", rel(b.slices())}};
  };
  Json j;
  j["format"] = "mesocap-session-layout";
  j["format_version"] = 1;
  j["root"] = fs::absolute(root_).lexically_normal().string();
  j["note"] = "paths relative to root; BB is a board id (two digits), NNNN a shot index, K and KKKK a count, "
              "III of NNN a shard, STAGE a stage, KEY its inputs hash, JOB a workflow job";
  j["capture"] = {{"manifest", rel(manifest())},
                  {"journal", rel(journal())},
                  {"shots", rel(shots())},
                  {"calib", rel(calib())},
                  {"shot_file", ShotEntry("shot", kPattern, ".jpg")},
                  {"calib_file", ShotEntry("calib", kPattern, ".jpg")},
                  {"truth", rel(truth())},
                  {"rig_layout", rel(rig_layout())},
                  {"simulate_report", rel(simulate_report())},
                  {"import_report", rel(import_report())},
                  {"capture_report", rel(capture_report())}};
  j["lock"] = rel(lock());
  j["stage_cache"] = rel(stage_cache());
  j["calibration"] = {{"folder", rel(c.root)},
                      {"rig", rel(c.rig())},
                      {"report", rel(c.report())},
                      {"lights_plot", rel(c.lights_plot())},
                      {"intrinsics_plot", rel(c.intrinsics_plot())},
                      {"flash_positions_plot", rel(c.flash_positions_plot())}};
  j["slices"] = {{"folder", rel(s.root)},
                 {"index", rel(s.index())},
                 {"board_lights", rel(s.board_lights(kPattern))},
                 {"slice", rel(s.root / SlicesFolder::SliceEntry(kPattern, ShotStem("shot", kPattern)))}};
  j["ptm"] = {{"folder", rel(p.root)},
              {"board_ptm", rel(p.board_ptm(kPattern))},
              {"board_residual_exr", rel(p.board_residual(kPattern, ".exr"))},
              {"board_residual_png", rel(p.board_residual(kPattern, ".png"))},
              {"report", rel(p.report())}};
  j["btf"] = btf_folder(btf());
  j["synth"] = {{"folder", rel(y.root)},          {"map", rel(y.map())},         {"patches", rel(y.patches())},
                {"image", rel(y.image())},        {"ptm", rel(y.ptm())},         {"preview", rel(y.preview())},
                {"preview_light", rel(y.preview_light(kPattern))}, {"textons", rel(y.textons())},
                {"report", rel(y.report())},      {"btf", btf_folder(y.btf())}};
  const DecorateFolder d = decorate("MESH");
  j["decorate"] = {{"folder", rel(decorate_root())},
                   {"mesh_folder", rel(d.root)},
                   {"surface_map", rel(d.surface_map())},
                   {"textons", rel(d.textons())},
                   {"report", rel(d.report())},
                   {"preview_light", rel(d.preview_light(0))},
                   {"sweep_frame", rel(d.sweep_frame(kPattern))},
                   {"gltf", gltf(d.gltf(), false)}};
  j["export"] = {{"folder", rel(e.root)},
                 {"material_ptm", rel(e.material_ptm())},
                 {"lp", rel(e.lp())},
                 {"lp_file", rel(e.lp_file())},
                 {"lp_slice", rel(e.lp_slice(kPattern))},
                 {"btf", btf_folder(e.btf())},
                 {"btf_multipart", rel(e.btf_multipart())},
                 {"gltf", gltf(e.gltf(), true)},
                 {"gltf_synth", gltf(e.gltf_synth(), false)},
                 {"previews",
                  {{"folder", rel(v.root)},
                   {"ptm_relit", rel(v.ptm_relit())},
                   {"btf_slices", rel(v.btf_slices())},
                   {"material_sphere", rel(v.material_sphere())},
                   {"material_cloth", rel(v.material_cloth())},
                   {"viewer", rel(v.viewer())}}}};
  j["coverage"] = {{"folder", rel(coverage().root)},
                   {"assessment", rel(coverage().assessment())},
                   {"plot", rel(coverage().plot())}};
  const ShardsFolder shards_pattern = shards("", "");
  j["shards"] = {{"folder", rel(shards_root())},
                 {"stage_key", rel(shards_pattern.root)},
                 {"shared", rel(shards_pattern.shared())},
                 {"statistics", rel(shards_pattern.shared() / ShardsFolder::statistics_name())},
                 {"part", rel(shards_pattern.part(kPattern, kPattern))},
                 {"part_record", ShardsFolder::part_record_name()}};
  j["workflow"] = {{"folder", rel(workflow())}, {"marker", rel(workflow_marker(""))}, {"log", rel(workflow_log(""))}};
  j["console"] = {{"folder", rel(console())}, {"thumbnail", rel(console_thumbnail("shot_0001.jpg"))},
                  {"view", rel(console_view("shot_0001.jpg"))},
                  {"process_log", rel(console_process_log())}};
  j["report"] = {{"html", rel(report_html())},
                 {"markdown", rel(report_md())},
                 {"files", rel(report_files())},
                 {"light_coverage_plot", rel(light_coverage_plot())}};
  return j;
}

}  // namespace mesocap

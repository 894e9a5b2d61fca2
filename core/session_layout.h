// Where everything of a session lives (docs/formats.md, "Session folder"): the one place the
// names of its files and folders are spelled (core/session_layout.cc; a test checks that no other
// source spells them). Each folder a stage writes is a type of its own over any root, since the
// stage writes it into a staging folder first and some (a BTF, a synthesis, an export) are also
// written outside sessions. Scripts and pages get these paths from `mesocap layout SESSION --json`.
#pragma once

#include <filesystem>
#include <string>

#include "core/json.h"

namespace mesocap {

// As a board id, shot index or count: the name's pattern ("board_BB", "shot_NNNN"), for
// `mesocap layout`.
inline constexpr int kPattern = -1;

// A BTF folder: index.json and slices/ (mesocap reconstruct, simulate --true-btf, a synthesis
// of a BTF, export's exr).
struct BtfFolder {
  std::filesystem::path root;
  std::filesystem::path index() const;
  std::filesystem::path slices() const;
  // `name` (a slice's file name) relative to the root, as index.json lists it.
  static std::string SliceEntry(const std::string& name);
};

// calibration/: what `mesocap calibrate` estimated.
struct CalibrationFolder {
  std::filesystem::path root;
  std::filesystem::path rig() const;                // rig.json
  std::filesystem::path report() const;             // report.json
  std::filesystem::path lights_plot() const;        // flash directions, polar
  std::filesystem::path intrinsics_plot() const;    // checkerboard residuals
  std::filesystem::path flash_positions_plot() const;
};

// slices/: every lit board patch as a BTF slice.
struct SlicesFolder {
  std::filesystem::path root;
  std::filesystem::path index() const;
  std::filesystem::path board_lights(int board) const;  // board_BB.lp
  // Board `board`'s slice from shot file `shot_stem`, relative to the root (index.json's `file`).
  static std::string SliceEntry(int board, const std::string& shot_stem);
};

// ptm/: a PTM per board.
struct PtmFolder {
  std::filesystem::path root;
  std::filesystem::path board_ptm(int board) const;
  // The board's fit error map: `extension` ".exr" (values) or ".png" (to see).
  std::filesystem::path board_residual(int board, const std::string& extension) const;
  std::filesystem::path report() const;
};

// A synthesis folder (mesocap synth, synth-apply, paint; SESSION/synth/).
struct SynthFolder {
  std::filesystem::path root;
  std::filesystem::path map() const;        // map.exr
  std::filesystem::path patches() const;    // patches.png
  std::filesystem::path image() const;      // synth.exr (an image exemplar)
  std::filesystem::path ptm() const;        // synth.ptm (a PTM exemplar)
  std::filesystem::path preview() const;    // preview.png
  std::filesystem::path preview_light(int k) const;
  std::filesystem::path textons() const;    // textons.exr (texton synthesis's analysis)
  std::filesystem::path report() const;
  BtfFolder btf() const { return {root}; }  // a BTF exemplar's slices
};

// A dressed mesh (mesocap decorate --out DIR).
struct DecorateFolder {
  std::filesystem::path root;
  std::filesystem::path surface_map() const;  // surface_map.ply
  std::filesystem::path textons() const;      // textons.exr (texton maps)
  std::filesystem::path atlas_map() const;    // atlas_map.exr (quilt maps: per atlas texel)
  std::filesystem::path report() const;
  std::filesystem::path previews() const;     // previews/
  std::filesystem::path preview_light(int k) const;  // previews/light_K.png
  std::filesystem::path sweep_frame(int k) const;    // previews/sweep_KK.png: a light circling the mesh
  struct GltfFolder gltf() const;                    // gltf/: the dressed mesh as a glTF asset
};

// A glTF material folder (export/gltf, export/gltf_synth).
struct GltfFolder {
  std::filesystem::path root;
  static std::string material_name();          // material.gltf
  static std::string buffer_name();            // material.bin
  static std::string base_color_name();        // the textures, as the .gltf refers to them
  static std::string metallic_roughness_name();
  static std::string normal_name();
  std::filesystem::path material() const { return root / material_name(); }
  std::filesystem::path buffer() const { return root / buffer_name(); }
  std::filesystem::path base_color() const { return root / base_color_name(); }
  std::filesystem::path metallic_roughness() const { return root / metallic_roughness_name(); }
  std::filesystem::path normal() const { return root / normal_name(); }
  std::filesystem::path fit_report() const;  // fit.json
  std::filesystem::path fit_error(const std::string& extension) const;  // ".png" or ".exr"
};

// previews/ in an export folder.
struct PreviewsFolder {
  std::filesystem::path root;
  std::filesystem::path ptm_relit() const;
  std::filesystem::path btf_slices() const;
  std::filesystem::path material_sphere() const;
  std::filesystem::path material_cloth() const;
  std::filesystem::path viewer() const;  // the WebGL relighting page
};

// An export folder (mesocap export --out, SESSION/export/).
struct ExportFolder {
  std::filesystem::path root;
  std::filesystem::path material_ptm() const;
  std::filesystem::path lp() const;                 // lp/: the slices as PNGs and their .lp
  std::filesystem::path lp_file() const;            // lp/material.lp
  std::filesystem::path lp_slice(int k) const;      // lp/slice_KKKK.png
  BtfFolder btf() const;
  std::filesystem::path btf_multipart() const;      // btf.exr: every slice as a part
  GltfFolder gltf() const;
  GltfFolder gltf_synth() const;                    // of the synthesized map
  PreviewsFolder previews() const;
};

// A capture-guidance folder (mesocap coverage).
struct CoverageFolder {
  std::filesystem::path root;
  std::filesystem::path assessment() const;  // coverage.json
  std::filesystem::path plot() const;        // coverage.png
};

// A sharded stage's work before its merge, for one key (the stage's inputs hash): what every
// shard shares and each shard's part (docs/workflow.md).
struct ShardsFolder {
  std::filesystem::path root;
  // shared/: what every shard reads, made by the first shard (published whole).
  std::filesystem::path shared() const;
  std::filesystem::path shared_lock() const;  // held by the shard making shared/
  static std::string statistics_name();       // in shared/: the reconstruction's statistics.bin
  // Shard `index` of `count`'s part (a folder, published whole) and its record inside it.
  std::filesystem::path part(int index, int count) const;
  std::filesystem::path part_lock(int index, int count) const;
  static std::string part_record_name();      // part.json
};

class SessionLayout {
 public:
  explicit SessionLayout(std::filesystem::path root) : root_(std::move(root)) {}
  const std::filesystem::path& root() const { return root_; }

  // Written by capture, import or simulate.
  std::filesystem::path manifest() const;         // session.json
  std::filesystem::path journal() const;          // journal.jsonl
  std::filesystem::path shots() const;            // flash shots
  std::filesystem::path calib() const;            // checkerboard shots
  // The folder of shots of `kind` ("shot" or "calib"), and shot `index`'s file relative to the
  // root (e.g. "shots/shot_0001.jpg"), as the journal records it.
  std::filesystem::path shots_of_kind(const std::string& kind) const;
  static std::string ShotEntry(const std::string& kind, int index, const std::string& extension);
  // Shot `index`'s file name without folder or extension ("shot_0001").
  static std::string ShotStem(const std::string& kind, int index);
  // The index in a shot file's name ("shot_0001.jpg" -> 1) for `kind`; 0 for any other name.
  static int ShotIndexOf(const std::string& kind, const std::string& file_name);
  std::filesystem::path truth() const;            // virtual sessions: the ground truth
  std::filesystem::path rig_layout() const;
  std::filesystem::path simulate_report() const;
  std::filesystem::path import_report() const;
  std::filesystem::path capture_report() const;
  std::filesystem::path lock() const;             // the writers' lock
  std::filesystem::path stage_cache() const;      // stages.json

  // One folder per stage.
  CalibrationFolder calibration() const;
  SlicesFolder slices() const;
  PtmFolder ptm() const;
  BtfFolder btf() const;
  SynthFolder synth() const;
  // decorate/: process --decorate's dressed meshes, one folder per mesh (named after its file).
  std::filesystem::path decorate_root() const;
  DecorateFolder decorate(const std::string& mesh_name) const;
  ExportFolder exports() const;
  CoverageFolder coverage() const;
  // shards/: sharded stages' parts, by stage and key ("" for the pattern), removed by the merge.
  std::filesystem::path shards_root() const;
  ShardsFolder shards(const std::string& stage, const std::string& key) const;
  // workflow/: the Snakemake workflow's marker per finished job (workflow/Snakefile).
  std::filesystem::path workflow() const;
  std::filesystem::path workflow_marker(const std::string& job) const;  // JOB.done
  std::filesystem::path workflow_log(const std::string& job) const;     // JOB.log
  // console/: the capture console's thumbnails of the shots (`mesocap console`), and its log of
  // the finishing `process` run.
  std::filesystem::path console() const;
  std::filesystem::path console_thumbnail(const std::string& shot_file) const;  // console/thumbs/shot_0001.jpg
  std::filesystem::path console_view(const std::string& shot_file) const;       // console/views/shot_0001.jpg
  std::filesystem::path console_process_log() const;                            // console/process.log

  // The session's report (Report::Write names the files in a folder) and its pictures.
  std::filesystem::path report_html() const;
  std::filesystem::path report_md() const;
  std::filesystem::path report_files() const;
  std::filesystem::path light_coverage_plot() const;

  // `path` relative to the root, with '/' (for links in the report and records in JSON files).
  std::string Relative(const std::filesystem::path& path) const;
  // Every file and folder above, by name: what `mesocap layout --json` prints.
  Json ToJson() const;

 private:
  std::filesystem::path root_;
};

// `path` relative to `base`, with '/': a link in a report beside `base`, a path in a record.
std::string RelativePath(const std::filesystem::path& path, const std::filesystem::path& base);

// For help texts and messages: the layout of a session called SESSION ("SESSION/rig_layout.json").
inline SessionLayout HelpLayout() { return SessionLayout("SESSION"); }
// A folder's own name with a slash ("calib/"), as help texts name one.
inline std::string FolderName(const std::filesystem::path& folder) { return folder.filename().string() + "/"; }

// The report files Report::Write puts in a folder.
std::string ReportHtmlName();
std::string ReportMarkdownName();

}  // namespace mesocap

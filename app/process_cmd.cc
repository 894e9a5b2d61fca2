// mesocap process SESSION: every stage from the shots to the exports, in order, skipping a stage
// whose inputs and options are unchanged since it last ran (core/stage_cache.h). An interrupted
// run resumes at the stage it was in; each stage's folder appears whole. Ends with a summary
// table and SESSION/report.html.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <set>

#include "app/btf_folder.h"
#include "app/commands.h"
#include "app/session_export.h"
#include "app/session_stages.h"
#include "core/atomic_file.h"
#include "core/content_hash.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "core/provenance.h"
#include "core/session.h"
#include "core/slice_index.h"
#include "core/stage_cache.h"
#include "export/previews.h"
#include "export/ptm_file.h"
#include "export/report.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;

struct ProcessArgs {
  fs::path session;
  CalibrateStageOptions calibrate;
  ResampleOptions resample;
  bool no_brdf_smoothing = false;
  std::string ptm_format = "rgb";
  PtmStageOptions ptm;
  ReconstructStageOptions reconstruct;
  std::vector<std::string> force;
  int threads = -1;
  bool no_progress = false;
};

// One stage of the chain: what it reads (earlier stages' outputs, files of the session), the
// options that change what it writes, and where it writes.
struct Stage {
  std::string name;
  std::vector<std::string> after;    // earlier stages whose outputs it reads
  std::vector<fs::path> input_files;  // files and folders it reads besides those
  Json options;
  std::vector<std::string> outputs;   // relative to the session
  std::function<StatusOr<StageSummary>()> run;
};

struct StageOutcome {
  std::string name, status;  // "ran" / "skipped (unchanged)"
  double seconds = 0;
  StageSummary summary;
};

// Pictures for the report: the top board's PTM relit under three lights, and a few
// reconstructed slices, in SESSION/export/previews/ (built in `dir`).
Status WritePreviews(const fs::path& session, const fs::path& dir, std::vector<std::string>* written) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return Status::Error(dir.string() + ": cannot create: " + ec.message());
  auto top = TopBoardOfSession(session);
  if (!top.ok()) return top.status();
  if (auto ptm = ReadPtmFile(BoardPtmFile(session, *top)); ptm.ok()) {
    std::vector<Image> lit;
    std::vector<std::string> labels;
    for (double phi : {0.0, 120.0, 240.0}) {
      lit.push_back(RelightPtm(*ptm, DirectionFromAnglesDeg(45, phi)));
      labels.push_back(Format("PTM, light (45, %.0f)", phi));
    }
    MESOCAP_RETURN_IF_ERROR(WriteImage(dir / "ptm_relit.jpg", ContactSheet(ExposeTogether(lit), labels, 3, 300),
                                       {.format = PixelFormat::kUint8Srgb}));
    written->push_back("ptm_relit.jpg");
  }
  auto btf = ReadSliceIndex(session / "btf" / "index.json");
  if (!btf.ok()) return btf.status();
  std::vector<Image> slices;
  std::vector<std::string> labels;
  const size_t shown = std::min<size_t>(8, btf->slices.size());
  for (size_t k = 0; k < shown; ++k) {
    // Spread over lights and views alike (the index runs light-fastest within each view).
    const SliceIndexEntry& e = btf->slices[(k * btf->slices.size() / shown + 5 * k) % btf->slices.size()];
    auto image = ReadImage(e.file);
    if (!image.ok()) return image.status();
    slices.push_back(std::move(*image));
    labels.push_back(Format("i(%.0f,%.0f) o(%.0f,%.0f)", e.theta_i_deg, e.phi_i_deg, e.theta_o_deg, e.phi_o_deg));
  }
  MESOCAP_RETURN_IF_ERROR(WriteImage(dir / "btf_slices.jpg", ContactSheet(ExposeTogether(slices), labels, 4, 200),
                                     {.format = PixelFormat::kUint8Srgb}));
  written->push_back("btf_slices.jpg");
  return Status::Ok();
}

// SESSION/export/: every format of `mesocap export` plus previews, swapped in whole.
StatusOr<StageSummary> RunExportStage(const fs::path& session) {
  auto staging = StagingFolder::Begin(session / "export");
  if (!staging.ok()) return staging.status();
  StageSummary summary;
  for (ExportFormat format : AllExportFormats()) {
    auto written = ExportSession(session, format, staging->path());
    if (!written.ok()) return written.status();
  }
  std::vector<std::string> previews;
  MESOCAP_RETURN_IF_ERROR(WritePreviews(session, staging->path() / "previews", &previews));
  MESOCAP_RETURN_IF_ERROR(staging->Publish(/*replace=*/true));
  summary.brief = "material.ptm, lp/material.lp, btf/ (OpenEXR), previews/";
  summary.report = {{"previews", previews}};
  return summary;
}

std::vector<Stage> MakeStages(const ProcessArgs& a) {
  const fs::path& s = a.session;
  const fs::path layout = a.calibrate.layout_file.empty() ? s / "rig_layout.json" : a.calibrate.layout_file;
  std::vector<fs::path> calibrate_inputs = {s / Session::kJournalName, s / "shots", layout};
  if (fs::exists(s / "calib")) calibrate_inputs.push_back(s / "calib");
  if (!a.calibrate.camera_file.empty()) calibrate_inputs.push_back(a.calibrate.camera_file);
  if (!a.calibrate.calibrate.marked_corners.empty()) calibrate_inputs.push_back(a.calibrate.calibrate.marked_corners);
  const bool progress = !a.no_progress;
  std::vector<Stage> stages;
  stages.push_back({"calibrate", {}, calibrate_inputs,
                    {{"pose_shots", a.calibrate.calibrate.pose_shots},
                     {"camera_file", a.calibrate.camera_file.string()},
                     {"marked_corners", a.calibrate.calibrate.marked_corners.string()}},
                    {"calibration"},
                    [&a] { return RunCalibrateStage(a.calibrate); }});
  stages.push_back({"resample", {"calibrate"}, {s / "shots", layout}, a.resample.ToJson(), {"slices"},
                    [&a, progress] { return RunResampleStage(a.session, a.calibrate.layout_file, a.resample, progress); }});
  stages.push_back({"fit-ptm", {"resample"}, {layout},
                    {{"format", PtmFormatToString(a.ptm.format)}, {"min_slices", a.ptm.min_slices}},
                    {"ptm"},
                    [&a, progress] { return RunPtmStage(a.session, a.calibrate.layout_file, a.ptm, progress); }});
  stages.push_back({"reconstruct", {"resample"}, {},
                    {{"size", a.reconstruct.slices.size}, {"grid", a.reconstruct.grid},
                     {"pixel_only", a.reconstruct.pixel_only}},
                    {"btf"},
                    [&a, progress] { return RunReconstructStage(a.session, a.reconstruct, progress); }});
  stages.push_back({"export", {"resample", "fit-ptm", "reconstruct"}, {}, {{"formats", "ptm lp exr previews"}},
                    {"export"},
                    [&a] { return RunExportStage(a.session); }});
  return stages;
}

const std::vector<std::string>& StageNames() {
  static const std::vector<std::string> names = {"calibrate", "resample", "fit-ptm", "reconstruct", "export"};
  return names;
}

// Hash of everything a stage reads: program version, stage name, options, the recorded outputs
// of the stages it follows and the contents of its input files (hashed once per run).
StatusOr<std::string> InputsHash(const Stage& stage, const StageCache& cache,
                                 std::map<fs::path, std::string>* file_hashes) {
  ContentHasher h;
  h.Add(Version());
  h.Add(stage.name);
  h.Add(stage.options.dump());
  for (const std::string& before : stage.after) {
    auto outputs = cache.OutputsHash(before);
    if (!outputs.ok()) return outputs.status();
    h.Add(before);
    h.Add(*outputs);
  }
  for (const fs::path& file : stage.input_files) {
    auto it = file_hashes->find(file);
    if (it == file_hashes->end()) {
      auto hash = HashPath(file);
      if (!hash.ok()) return hash.status();
      it = file_hashes->emplace(file, *hash).first;
    }
    h.Add(file.filename().string());
    h.Add(it->second);
  }
  return h.Hex();
}

void PrintSummary(const std::vector<StageOutcome>& outcomes) {
  std::printf("\n%-12s %-22s %9s  %s\n", "stage", "status", "seconds", "outputs");
  for (const StageOutcome& o : outcomes) {
    std::printf("%-12s %-22s %9.1f  %s\n", o.name.c_str(), o.status.c_str(), o.seconds, o.summary.brief.c_str());
    for (const std::string& w : o.summary.warnings) std::printf("%-12s   warning: %s\n", "", w.c_str());
  }
}

Status WriteProcessReport(const fs::path& session, const std::vector<StageOutcome>& outcomes) {
  Report report("mesocap process: " + fs::absolute(session).filename().string());
  report.Paragraph("Every stage of the session's processing, from the shots to the exports. A stage whose inputs and "
                   "options did not change since it last ran was skipped (SESSION/stages.json).");
  std::vector<std::vector<std::string>> rows;
  for (const StageOutcome& o : outcomes)
    rows.push_back({o.name, o.status, Format("%.1f", o.seconds), o.summary.brief, std::to_string(o.summary.warnings.size())});
  report.Table({"stage", "status", "seconds", "outputs", "warnings"}, rows);
  report.Heading("Calibration");
  if (fs::exists(session / "calibration" / "lights.png"))
    report.Picture("calibration/lights.png", "Flash directions seen from the top board (centre: zenith)");
  if (fs::exists(session / "calibration" / "intrinsics_residuals.png"))
    report.Picture("calibration/intrinsics_residuals.png", "Checkerboard corner residuals of the camera calibration");
  report.Heading("Rejected shots, skipped slices and other warnings");
  std::vector<std::vector<std::string>> warnings;
  for (const StageOutcome& o : outcomes)
    for (const std::string& w : o.summary.warnings) warnings.push_back({o.name, w});
  if (warnings.empty()) report.Paragraph("None.");
  else report.Table({"stage", "warning"}, warnings);
  report.Heading("Results");
  if (fs::exists(session / "export" / "previews" / "ptm_relit.jpg"))
    report.Picture("export/previews/ptm_relit.jpg", "The top board's PTM (export/material.ptm) relit under three lights");
  if (fs::exists(session / "export" / "previews" / "btf_slices.jpg"))
    report.Picture("export/previews/btf_slices.jpg", "Slices of the reconstructed BTF (export/btf/), one exposure");
  report.Paragraph("Files: calibration/ (rig.json, report.json), slices/ (measured BTF slices, index.json, board_BB.lp), "
                   "ptm/ (one PTM per board), btf/ (the reconstructed BTF), export/ (material.ptm, lp/, btf/, previews/). "
                   "Formats: docs/formats.md.");
  return report.Write(session);
}

int Run(ProcessArgs& a) {
  const std::string verb = "process";
  std::set<std::string> force(a.force.begin(), a.force.end());
  for (const std::string& f : force)
    if (f != "all" && std::count(StageNames().begin(), StageNames().end(), f) == 0)
      return Fail(verb, "--force " + f + ": no such stage (calibrate, resample, fit-ptm, reconstruct, export, all)", kExitUsage);
  if (!StringToPtmFormat(a.ptm_format, &a.ptm.format))
    return Fail(verb, "--ptm-format must be lrgb or rgb, not '" + a.ptm_format + "'", kExitUsage);
  if (GridPairs(a.reconstruct.grid).empty())
    return Fail(verb, "--btf-grid must be bonn or coarse, not '" + a.reconstruct.grid + "'", kExitUsage);
  a.calibrate.calibrate.session = a.session;
  a.calibrate.calibrate.num_threads = a.threads;
  a.calibrate.progress = !a.no_progress;
  a.resample.brdf_smoothing = !a.no_brdf_smoothing;
  a.resample.num_threads = a.threads;
  a.reconstruct.slices.btf.num_threads = a.threads;
  if (std::string why = a.calibrate.calibrate.Check(); !why.empty()) return Fail(verb, why, kExitUsage);
  if (std::string why = a.resample.Check(); !why.empty()) return Fail(verb, why, kExitUsage);
  if (!a.reconstruct.slices.Check()) return Fail(verb, "--btf-size must be a power of two", kExitUsage);
  if (auto session = Session::Open(a.session); !session.ok()) return Fail(verb, session.status().message());

  auto cache = StageCache::Open(a.session);
  if (!cache.ok()) return Fail(verb, cache.status().message());
  const std::vector<Stage> stages = MakeStages(a);
  std::map<fs::path, std::string> file_hashes;
  std::vector<StageOutcome> outcomes;
  for (size_t k = 0; k < stages.size(); ++k) {
    const Stage& stage = stages[k];
    auto inputs = InputsHash(stage, *cache, &file_hashes);
    if (!inputs.ok()) return Fail(verb, "stage " + stage.name + ": " + inputs.status().message());
    std::string why = force.count(stage.name) || force.count("all") ? "forced" : cache->WhyRun(stage.name, *inputs);
    StageOutcome outcome{stage.name, "", 0, {}};
    if (why.empty()) {
      const StageRecord* record = cache->Find(stage.name);
      outcome.status = "skipped (unchanged)";
      outcome.summary.brief = record->summary.value("brief", "");
      for (const Json& w : record->summary.value("warnings", Json::array())) outcome.summary.warnings.push_back(w.get<std::string>());
      std::fprintf(stderr, "[%zu/%zu] %s: unchanged, skipped\n", k + 1, stages.size(), stage.name.c_str());
      outcomes.push_back(outcome);
      continue;
    }
    std::fprintf(stderr, "[%zu/%zu] %s: running (%s)\n", k + 1, stages.size(), stage.name.c_str(), why.c_str());
    const auto start = std::chrono::steady_clock::now();
    auto summary = stage.run();
    if (!summary.ok()) return Fail(verb, "stage " + stage.name + ": " + summary.status().message());
    outcome.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    outcome.status = "ran";
    outcome.summary = *summary;
    StageRecord record;
    record.inputs_hash = *inputs;
    record.outputs = stage.outputs;
    record.seconds = outcome.seconds;
    record.finished_utc = UtcNowIso8601();
    record.summary = {{"brief", summary->brief}, {"warnings", summary->warnings}, {"report", summary->report}};
    if (Status st = cache->Record(stage.name, record); !st.ok()) return Fail(verb, st.message());
    outcomes.push_back(outcome);
  }
  PrintSummary(outcomes);
  if (Status st = WriteProcessReport(a.session, outcomes); !st.ok()) return Fail(verb, st.message());
  std::printf("process: done -> %s\n", (a.session / "report.html").string().c_str());
  return kExitOk;
}

}  // namespace

Command ProcessCommand() {
  auto args = std::make_shared<ProcessArgs>();
  args->resample.slice_size = 256;
  args->reconstruct.slices.size = 128;
  Command c;
  c.name = "process";
  c.setup = [args](CLI::App& app) {
    CLI::App* sub = app.add_subcommand(
        "process", "Run every stage on a session (calibrate, resample, fit-ptm, reconstruct, export), skipping unchanged ones");
    sub->add_option("session", args->session, "Session folder (from capture, import or simulate)")->required();
    sub->add_option("--camera", args->calibrate.camera_file,
                    "Intrinsics (camera.json from calibrate-camera); default: from the session's calib/ shots");
    sub->add_option("--layout", args->calibrate.layout_file, "Rig layout (default SESSION/rig_layout.json)");
    sub->add_option("--pose-shots", args->calibrate.calibrate.pose_shots, "Shots searched for AprilTags")->capture_default_str();
    sub->add_option("--marked-corners", args->calibrate.calibrate.marked_corners, "Hand-marked board corners (docs/formats.md)");
    sub->add_option("--slice-size", args->resample.slice_size, "Texels per side of each measured BTF slice")->capture_default_str();
    sub->add_flag("--no-brdf-smoothing", args->no_brdf_smoothing, "Do not rescale slices to the smoothed average BRDF");
    sub->add_option("--ptm-format", args->ptm_format, "PTM of each board: rgb or lrgb")->capture_default_str();
    sub->add_option("--btf-size", args->reconstruct.slices.size, "Texels per side of the reconstructed BTF (power of two)")
        ->capture_default_str();
    sub->add_option("--btf-grid", args->reconstruct.grid, "Direction pairs of the reconstructed BTF: bonn (6561) or coarse (289)")
        ->capture_default_str();
    sub->add_flag("--btf-pixel-only", args->reconstruct.pixel_only, "Reconstruct from pixel histograms only (no subbands)");
    sub->add_option("--force", args->force, "Rerun this stage even if unchanged (repeatable; 'all' for every stage)");
    sub->add_option("--threads", args->threads, "Threads (-1: all cores)")->capture_default_str();
    sub->add_flag("--no-progress", args->no_progress, "Do not draw progress bars");
  };
  c.run = [args]() { return Run(*args); };
  return c;
}

}  // namespace mesocap::app

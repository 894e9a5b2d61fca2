#include "app/process.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <map>
#include <optional>
#include <set>

#include "app/btf_folder.h"
#include "app/ggx_shards.h"
#include "app/reconstruct_shards.h"
#include "app/shard_parts.h"
#include "app/synth_stage.h"
#include "app/session_export.h"
#include "app/synth_run.h"
#include "core/atomic_file.h"
#include "core/content_hash.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "core/provenance.h"
#include "core/session.h"
#include "core/session_layout.h"
#include "core/session_lock.h"
#include "core/slice_index.h"
#include "core/stage_cache.h"
#include "core/stage_versions.h"
#include "core/text_format.h"
#include "export/gltf_material.h"
#include "export/material_preview.h"
#include "export/previews.h"
#include "formats/ptm_file.h"
#include "export/viewer_page.h"

namespace mesocap::app {

namespace fs = std::filesystem;

namespace {

struct Stage {
  std::string name;
  std::vector<std::string> after;    // earlier stages whose outputs it reads
  std::vector<fs::path> input_files;  // files and folders it reads besides those
  Json options;
  std::vector<std::string> outputs;   // relative to the session
  std::function<StatusOr<StageSummary>()> run;
  // A shardable stage's shard (`key` its inputs hash; sets *done_before when its part was there)
  // and merge; null for the others.
  std::function<StatusOr<StageSummary>(const Shard&, const std::string& key, bool* done_before)> run_shard = nullptr;
  // `make_command`: the command that makes a shard, for the message naming a missing one.
  std::function<StatusOr<StageSummary>(int count, const std::string& key, const std::string& make_command)> merge = nullptr;
};

// Pictures for the report: the top board's PTM relit under three lights, the glTF material of
// `exports` (built there) and a few reconstructed slices, in its previews/.
Status WritePreviews(const fs::path& session, const ExportFolder& exports, std::vector<std::string>* written) {
  const PreviewsFolder previews = exports.previews();
  const fs::path& dir = previews.root;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return Status::Error(dir.string() + ": cannot create: " + ec.message());
  auto top = TopBoardOfSession(session);
  if (!top.ok()) return top.status();
  if (auto ptm = ReadPtmFile(SessionLayout(session).ptm().board_ptm(*top)); ptm.ok()) {
    std::vector<Image> lit;
    std::vector<std::string> labels;
    for (double phi : {0.0, 120.0, 240.0}) {
      lit.push_back(RelightPtm(*ptm, DirectionFromAnglesDeg(45, phi)));
      labels.push_back(Format("PTM, light (45, %.0f)", phi));
    }
    MESOCAP_RETURN_IF_ERROR(WriteImage(previews.ptm_relit(), ContactSheet(ExposeTogether(lit), labels, 3, 300),
                                       {.format = PixelFormat::kUint8Srgb}));
    written->push_back(previews.ptm_relit().filename().string());
  }
  // The glTF material on a sphere and a draped sheet under three lights.
  if (auto maps = ReadGltfMaterialTextures(exports.gltf()); maps.ok()) {
    std::vector<Image> spheres, cloths;
    std::vector<std::string> labels;
    for (double phi : {30.0, 150.0, 270.0}) {
      const Eigen::Vector3d light = DirectionFromAnglesDeg(40, phi);
      spheres.push_back(RenderMaterialSphere(*maps, light, 300));
      cloths.push_back(RenderMaterialCloth(*maps, light, 300));
      labels.push_back(Format("light (40, %.0f)", phi));
    }
    MESOCAP_RETURN_IF_ERROR(WriteImage(previews.material_sphere(),
                                       ContactSheet(ExposeTogether(spheres), labels, 3, 300), {.format = PixelFormat::kUint8Srgb}));
    MESOCAP_RETURN_IF_ERROR(WriteImage(previews.material_cloth(), ContactSheet(ExposeTogether(cloths), labels, 3, 300),
                                       {.format = PixelFormat::kUint8Srgb}));
    written->insert(written->end(), {previews.material_sphere().filename().string(),
                                     previews.material_cloth().filename().string()});
  }
  auto btf = ReadSliceIndex(SessionLayout(session).btf().index());
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
  MESOCAP_RETURN_IF_ERROR(WriteImage(previews.btf_slices(), ContactSheet(ExposeTogether(slices), labels, 4, 200),
                                     {.format = PixelFormat::kUint8Srgb}));
  written->push_back(previews.btf_slices().filename().string());
  return Status::Ok();
}

// The report's WebGL viewer (export/viewer_page.h) as an HTML fragment in `previews`: the
// top board's PTM and, of the reconstructed BTF, the slices whose light and view both lie on the
// coarse grid (all of a coarse BTF, 289 of the Bonn grid's). Built here, once per export, so a
// `process` run that skips every stage does not rebuild it.
Status WriteViewer(const fs::path& session, const PreviewsFolder& previews) {
  std::optional<Ptm> ptm;
  if (auto top = TopBoardOfSession(session); top.ok())
    if (auto read = ReadPtmFile(SessionLayout(session).ptm().board_ptm(*top)); read.ok()) ptm = std::move(*read);
  std::vector<ViewerSlice> slices;
  if (auto btf = ReadSliceIndex(SessionLayout(session).btf().index()); btf.ok()) {
    for (const SliceIndexEntry& e : btf->slices) {
      if (!OnCoarseGrid(e.light) || !OnCoarseGrid(e.view)) continue;
      auto image = ReadImage(e.file);
      if (!image.ok()) return image.status();
      slices.push_back({e.light, e.view, std::move(*image)});
    }
  }
  if (!ptm && slices.empty()) return Status::Ok();
  auto html = ViewerHtml(ptm ? &*ptm : nullptr, slices, 64, previews.root);
  if (!html.ok()) return html.status();
  return WriteTextAtomically(previews.viewer(), *html);
}

// SESSION/export/: every format of `mesocap export` plus previews, swapped in whole.
StatusOr<StageSummary> RunExportStage(const fs::path& session, const GgxMaterialMaps* fitted = nullptr) {
  auto staging = StagingFolder::Begin(SessionLayout(session).exports().root);
  if (!staging.ok()) return staging.status();
  const ExportFolder staged{staging->path()};
  StageSummary summary;
  for (ExportFormat format : AllExportFormats()) {
    auto written = ExportSession(session, format, staging->path(), {.fitted = fitted});
    if (!written.ok()) return written.status();
  }
  std::vector<std::string> previews;
  MESOCAP_RETURN_IF_ERROR(WritePreviews(session, staged, &previews));
  MESOCAP_RETURN_IF_ERROR(WriteViewer(session, staged.previews()));
  MESOCAP_RETURN_IF_ERROR(staging->Publish(/*replace=*/true));
  const auto rel = [&](const fs::path& p) { return RelativePath(p, staged.root); };
  summary.brief = rel(staged.material_ptm()) + ", " + rel(staged.lp_file()) + ", " + rel(staged.btf().root) + "/ (OpenEXR), " +
                  rel(staged.gltf().material()) + ", " + rel(staged.previews().root) + "/";
  summary.report = {{"previews", previews}};
  return summary;
}

std::vector<Stage> MakeStages(const ProcessOptions& a) {
  const SessionLayout s(a.session);
  const fs::path layout = SessionLayoutFile(a.session, a.calibrate.layout_file);
  std::vector<fs::path> calibrate_inputs = {s.journal(), s.shots(), layout};
  if (fs::exists(s.calib())) calibrate_inputs.push_back(s.calib());
  if (!a.calibrate.camera_file.empty()) calibrate_inputs.push_back(a.calibrate.camera_file);
  if (!a.calibrate.calibrate.marked_corners.empty()) calibrate_inputs.push_back(a.calibrate.calibrate.marked_corners);
  const bool progress = a.progress;
  std::vector<Stage> stages;
  stages.push_back({"calibrate", {}, calibrate_inputs,
                    {{"pose_shots", a.calibrate.calibrate.pose_shots},
                     {"camera_file", a.calibrate.camera_file.string()},
                     {"marked_corners", a.calibrate.calibrate.marked_corners.string()}},
                    {s.Relative(s.calibration().root)},
                    [&a] { return RunCalibrateStage(a.calibrate); }});
  stages.push_back({"resample", {"calibrate"}, {s.shots(), layout}, a.resample.ToJson(), {s.Relative(s.slices().root)},
                    [&a, progress] { return RunResampleStage(a.session, a.calibrate.layout_file, a.resample, progress); }});
  stages.push_back({"fit-ptm", {"resample"}, {layout},
                    {{"format", PtmFormatToString(a.ptm.format)}, {"min_slices", a.ptm.min_slices}},
                    {s.Relative(s.ptm().root)},
                    [&a, progress] { return RunPtmStage(a.session, a.calibrate.layout_file, a.ptm, progress); }});
  stages.push_back({"reconstruct", {"resample"}, {}, a.reconstruct.ToJson(), {s.Relative(s.btf().root)},
                    [&a, progress] { return RunReconstructStage(a.session, a.reconstruct, progress); },
                    [&a, progress](const Shard& shard, const std::string& key, bool* done_before) {
                      return RunReconstructShard(a.session, a.reconstruct, shard, key, progress, done_before);
                    },
                    [&a](int count, const std::string& key, const std::string& make_command) {
                      return MergeReconstructShards(a.session, a.reconstruct, count, key, make_command);
                    }});
  if (!a.synth.method.empty())
    stages.push_back({"synth", {"reconstruct"}, {},
                      {{"method", a.synth.method}, {"width", a.synth.width}, {"height", a.synth.height},
                       {"seed", a.synth.seed}, {"max_slices", a.synth.max_slices}},
                      {s.Relative(s.synth().root)},
                      [&a, progress] { return RunSynthStage(a.session, a.synth, a.threads, progress); },
                      [&a, progress](const Shard& shard, const std::string& key, bool* done_before) {
                        return RunSynthShard(a.session, a.synth, a.threads, shard, key, progress, done_before);
                      },
                      [&a](int count, const std::string& key, const std::string& make_command) {
                        return MergeSynthShards(a.session, a.synth, a.threads, count, key, make_command);
                      }});
  std::vector<std::string> export_after = {"resample", "fit-ptm", "reconstruct"};
  if (!a.synth.method.empty()) export_after.push_back("synth");
  stages.push_back({"export", export_after, {}, {{"formats", "ptm lp exr gltf previews"}}, {s.Relative(s.exports().root)},
                    [&a] { return RunExportStage(a.session); },
                    [&a, progress](const Shard& shard, const std::string& key, bool* done_before) {
                      return RunGgxShard(a.session, shard, key, a.threads, progress, done_before);
                    },
                    [&a](int count, const std::string& key, const std::string& make_command) -> StatusOr<StageSummary> {
                      auto maps = MergeGgxShards(a.session, count, key, make_command);
                      if (!maps.ok()) return maps.status();
                      auto summary = RunExportStage(a.session, &*maps);
                      if (summary.ok()) RemoveShardParts(SessionLayout(a.session), "export");
                      return summary;
                    }});
  if (!a.decorate.meshes.empty()) {
    Json names = Json::array();
    for (const fs::path& m : a.decorate.meshes) names.push_back(m.filename().string());
    stages.push_back({"decorate", {"reconstruct", "export"}, a.decorate.meshes,
                      {{"meshes", names}, {"method", a.decorate.methods}, {"seed", a.decorate.seed}, {"max_slices", a.decorate.max_slices},
                       {"preview_size", a.decorate.preview_size}, {"sweep_frames", a.decorate.sweep_frames},
                       {"atlas_size", a.decorate.atlas_size}, {"representative_slices", a.decorate.representative_slices}},
                      {s.Relative(s.decorate_root())},
                      [&a, progress] { return RunDecorateStage(a.session, a.decorate, a.threads, progress); }});
  }
  return stages;
}


// Hash of everything a stage reads: its name and algorithm version (core/stage_versions.h), its
// options, the stages it follows (each one's recorded key, so a new version upstream reruns every
// stage downstream, and its outputs as they are on disk) and the contents of its input files
// (hashed once per run).
StatusOr<std::string> InputsHash(const Stage& stage, const StageCache& cache,
                                 std::map<fs::path, std::string>* file_hashes) {
  ContentHasher h;
  h.Add(stage.name);
  h.Add("version " + std::to_string(StageVersion(stage.name)));
  h.Add(stage.options.dump());
  for (const std::string& before : stage.after) {
    auto outputs = cache.OutputsHash(before);
    if (!outputs.ok()) return outputs.status();
    h.Add(before);
    h.Add(cache.Find(before)->inputs_hash);
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

}  // namespace

const std::vector<std::string>& ProcessStageNames() {
  static const std::vector<std::string> names = {"calibrate", "resample", "fit-ptm", "reconstruct", "synth", "export", "decorate"};
  return names;
}

const std::vector<std::string>& ShardableStageNames() {
  static const std::vector<std::string> names = {"reconstruct", "synth", "export"};
  return names;
}

std::string ProcessOptions::Check() const {
  const auto is_one_of = [](const std::string& name, const std::vector<std::string>& names) {
    return std::count(names.begin(), names.end(), name) > 0;
  };
  for (const std::string& f : force)
    if (f != "all" && !is_one_of(f, ProcessStageNames()))
      return "--force " + f + ": no such stage (calibrate, resample, fit-ptm, reconstruct, synth, export, decorate, all)";
  if (!synth.method.empty() && !IsSynthMethod(synth.method))
    return "--synth must be roller, quilt, ptm-block or texton, not '" + synth.method + "'";
  if (GridPairs(reconstruct.grid).empty()) return "--btf-grid must be bonn or coarse, not '" + reconstruct.grid + "'";
  if (threads == 0 || threads < -1) return "--threads must be a positive number (or -1 for all cores)";
  if (!only_stage.empty() && !is_one_of(only_stage, ProcessStageNames()))
    return "--stage " + only_stage + ": no such stage (calibrate, resample, fit-ptm, reconstruct, synth, export, decorate)";
  if (only_stage == "synth" && synth.method.empty()) return "--stage synth needs --synth METHOD";
  if (only_stage == "decorate" && decorate.meshes.empty()) return "--stage decorate needs --decorate MESH";
  if (std::string problem = CheckDecorateMeshes(decorate.meshes, decorate.methods); !problem.empty()) return problem;
  if ((shard || merge_shards != 0) && !is_one_of(only_stage, ShardableStageNames()))
    return "--shard and --merge need --stage naming a shardable stage (reconstruct, synth, export)";
  if (shard && merge_shards != 0) return "give --shard or --merge, not both";
  if (merge_shards < 0 || merge_shards > Shard::kMaxCount) return "--merge must be a shard count from 1 to 999";
  if (std::string why = resample.Check(); !why.empty()) return why;
  if (!reconstruct.slices.Check()) return "--btf-size must be a power of two";
  return calibrate.calibrate.pose_shots < 1 ? "--pose-shots must be at least 1" : "";
}

namespace {

// The cache's record of a stage that ran.
StageRecord RecordOf(const Stage& stage, const StageCache& cache, const std::string& inputs, const StageOutcome& outcome) {
  StageRecord record;
  record.inputs_hash = inputs;
  record.version = StageVersion(stage.name);
  for (const std::string& before : stage.after)
    if (auto hash = cache.OutputsHash(before); hash.ok()) record.read[before] = *hash;
  record.outputs = stage.outputs;
  record.seconds = outcome.seconds;
  record.finished_utc = UtcNowIso8601();
  record.summary = {{"brief", outcome.summary.brief}, {"warnings", outcome.summary.warnings}, {"report", outcome.summary.report}};
  return record;
}

StageOutcome SkippedOutcome(const Stage& stage, const StageCache& cache) {
  StageOutcome outcome{stage.name, "skipped (unchanged)", 0, {}};
  const StageRecord* record = cache.Find(stage.name);
  const Json brief = record->summary.value("brief", Json(""));
  if (brief.is_string()) outcome.summary.brief = brief.get<std::string>();
  for (const Json& w : record->summary.value("warnings", Json::array()))
    if (w.is_string()) outcome.summary.warnings.push_back(w.get<std::string>());
  return outcome;
}

// Runs the stage (or its shard or merge, as `a` asks); a shard's outcome is not recorded: its
// stage is done only once merged.
StatusOr<StageOutcome> RunStage(const Stage& stage, const ProcessOptions& a, const std::string& inputs,
                                StageCache* cache) {
  StageOutcome outcome{stage.name, "ran", 0, {}};
  const std::string key = inputs.substr(0, 16);
  const auto start = std::chrono::steady_clock::now();
  StatusOr<StageSummary> summary = StageSummary{};
  bool done_before = false;
  if (a.shard)
    summary = stage.run_shard(*a.shard, key, &done_before);
  else if (a.merge_shards > 0)
    summary = stage.merge(a.merge_shards, key,
                          "mesocap process " + a.session.string() + " --stage " + stage.name + " (with this run's options)");
  else
    summary = stage.run();
  if (!summary.ok()) return summary.status().WithContext("stage " + stage.name + ": ");
  outcome.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  outcome.summary = *summary;
  if (a.shard) {
    outcome.status = "shard " + a.shard->Name() + (done_before ? " done before" : " ran");
    return outcome;
  }
  MESOCAP_RETURN_IF_ERROR(cache->Record(stage.name, RecordOf(stage, *cache, inputs, outcome)));
  return outcome;
}

}  // namespace

StatusOr<std::vector<StageOutcome>> RunProcess(const ProcessOptions& given) {
  ProcessOptions a = given;
  a.calibrate.calibrate.session = a.session;
  a.calibrate.calibrate.num_threads = a.threads;
  a.calibrate.progress = a.progress;
  a.resample.num_threads = a.threads;
  a.reconstruct.slices.btf.num_threads = a.threads;
  if (std::string why = a.Check(); !why.empty()) return Status::Error(why);
  if (auto session = Session::Open(a.session); !session.ok()) return session.status();
  // One writer at a time: stages.json is rewritten from memory after each stage. Shards write
  // only their own parts and record nothing: they share the lock.
  auto lock = a.shard ? SessionLock::AcquireShared(a.session) : SessionLock::Acquire(a.session, "process");
  if (!lock.ok()) return lock.status();
  a.reconstruct.method.TakeSessionMirrorImages(a.session);  // in the stage's key: a change reruns it
  const std::set<std::string> force(a.force.begin(), a.force.end());
  auto cache = StageCache::Open(a.session);
  if (!cache.ok()) return cache.status();
  const std::vector<Stage> stages = MakeStages(a);
  std::map<fs::path, std::string> file_hashes;
  std::vector<StageOutcome> outcomes;
  for (size_t k = 0; k < stages.size(); ++k) {
    const Stage& stage = stages[k];
    if (!a.only_stage.empty() && stage.name != a.only_stage) continue;
    auto inputs = InputsHash(stage, *cache, &file_hashes);
    if (!inputs.ok()) return Status::Error("stage " + stage.name + ": " + inputs.status().message());
    std::string why = force.count(stage.name) || force.count("all") ? "forced" : cache->WhyRun(stage.name, *inputs, StageVersion(stage.name));
    if (why.empty()) {
      std::fprintf(stderr, "[%zu/%zu] %s: unchanged, skipped\n", k + 1, stages.size(), stage.name.c_str());
      outcomes.push_back(SkippedOutcome(stage, *cache));
      continue;
    }
    const std::string part = a.shard ? " shard " + a.shard->Name() : a.merge_shards ? " merge" : "";
    std::fprintf(stderr, "[%zu/%zu] %s%s: running (%s)\n", k + 1, stages.size(), stage.name.c_str(), part.c_str(), why.c_str());
    auto outcome = RunStage(stage, a, *inputs, &*cache);
    if (!outcome.ok()) return outcome.status();
    outcomes.push_back(std::move(*outcome));
  }
  return outcomes;
}

void PrintProcessSummary(const std::vector<StageOutcome>& outcomes) {
  std::printf("\n%-12s %-22s %9s  %s\n", "stage", "status", "seconds", "outputs");
  for (const StageOutcome& o : outcomes) {
    std::printf("%-12s %-22s %9.1f  %s\n", o.name.c_str(), o.status.c_str(), o.seconds, o.summary.brief.c_str());
    for (const std::string& w : o.summary.warnings) std::printf("%-12s   warning: %s\n", "", w.c_str());
  }
}

}  // namespace mesocap::app

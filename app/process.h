// mesocap process, as a library the command and the demo share: every stage of a session from
// the shots to the exports, in order, skipping a stage whose inputs and options are unchanged
// since it last ran (core/stage_cache.h). An interrupted run resumes at the stage it was in;
// each stage's folder appears whole.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "app/decorate_stage.h"
#include "app/session_stages.h"
#include "core/shard.h"
#include "core/status.h"

namespace mesocap::app {

struct ProcessOptions {
  std::filesystem::path session;
  CalibrateStageOptions calibrate;  // calibrate.calibrate.session is set from `session`
  ResampleOptions resample;
  PtmStageOptions ptm;
  ReconstructStageOptions reconstruct;
  SynthStageOptions synth;  // synth.method empty: no synth stage
  DecorateStageOptions decorate;  // decorate.meshes empty: no decorate stage
  std::vector<std::string> force;  // stages to rerun even if unchanged; "all" for every one
  // One stage alone (its earlier stages must have run), as the workflow runs it; empty: all.
  std::string only_stage;
  // With only_stage, a shardable stage (ShardableStageNames): run this shard of it, or merge
  // this many shards (docs/workflow.md).
  std::optional<Shard> shard;
  int merge_shards = 0;
  int threads = -1;
  bool progress = true;
  ProcessOptions() {
    resample.slice_size = 256;
    reconstruct.slices.size = 128;
  }
  // Empty when valid, else the problem (a usage error). Call before RunProcess.
  std::string Check() const;
};

struct StageOutcome {
  std::string name, status;  // status: "ran", "skipped (unchanged)", "shard I/N ran", "shard I/N done before"
  double seconds = 0;
  StageSummary summary;
};

// calibrate, resample, fit-ptm, reconstruct, synth (only when asked), export, decorate (only when asked).
const std::vector<std::string>& ProcessStageNames();
// The stages that run as shards: reconstruct.
const std::vector<std::string>& ShardableStageNames();

// Runs or skips every stage (or the one asked, or its shard or merge); stops at the first stage
// that fails (its error names the stage).
StatusOr<std::vector<StageOutcome>> RunProcess(const ProcessOptions& options);

// The table on stdout, and SESSION/report.html (+ report.md).
void PrintProcessSummary(const std::vector<StageOutcome>& outcomes);
Status WriteProcessReport(const std::filesystem::path& session, const std::vector<StageOutcome>& outcomes);

}  // namespace mesocap::app

// The stages of a session's processing, each reading and writing folders inside the session
// (docs/formats.md) so any one can run alone: `mesocap calibrate`, `reconstruct` and `export`
// call them one at a time, `mesocap process` in order with caching (app/process_cmd.cc). Each
// writes its folder whole (a staging folder swapped in at the end) and returns a summary.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "app/btf_folder.h"
#include "app/btf_method_args.h"
#include "calib/calibrate.h"
#include "calib/resample.h"
#include "core/json.h"
#include "core/rig_layout.h"
#include "core/slice_index.h"
#include "core/status.h"
#include "reconstruct/ptm.h"
#include "reconstruct/slice_set.h"

namespace mesocap::app {

struct StageSummary {
  std::string brief;                  // one line for the terminal and the summary table
  std::vector<std::string> warnings;  // rejected shots, skipped boards ...
  Json report = Json::object();       // the stage's figures, kept in stages.json
};

// The rig layout: `layout_file`, or SESSION/rig_layout.json when empty.
std::filesystem::path SessionLayoutFile(const std::filesystem::path& session, const std::filesystem::path& layout_file);
StatusOr<RigLayout> LoadSessionLayout(const std::filesystem::path& session, const std::filesystem::path& layout_file);
// The session's calibration, SESSION/calibration/rig.json; the error names the file (and, when it
// is missing, says to run `mesocap calibrate` first).
StatusOr<CalibrationResult> LoadSessionCalibration(const std::filesystem::path& session);

struct CalibrateStageOptions {
  CalibrateOptions calibrate;          // calibrate.session is the session folder
  std::filesystem::path camera_file;   // intrinsics; empty: from the session's checkerboard shots
  std::filesystem::path layout_file;   // empty: SESSION/rig_layout.json
  bool progress = true;
};
// The intrinsics: `camera_file`, else calibrated from the session's checkerboard shots (then
// `intrinsics_report` and `residual_plot` are filled in).
StatusOr<CameraModel> CameraFor(const CalibrateStageOptions& options, const RigLayout& layout, Json* intrinsics_report,
                                Image* residual_plot);
// Intrinsics, board poses, balls, flash position and power per shot -> SESSION/calibration/
// (rig.json, report.json, intrinsics_residuals.png, lights.png, flash_positions.png).
StatusOr<StageSummary> RunCalibrateStage(const CalibrateStageOptions& options);

// SESSION/calibration/rig.json -> every lit board patch as a BTF slice in SESSION/slices/
// (index.json, board_BB.lp).
StatusOr<StageSummary> RunResampleStage(const std::filesystem::path& session, const std::filesystem::path& layout_file,
                                        const ResampleOptions& options, bool progress);

struct PtmStageOptions {
  PtmFormat format = PtmFormat::kRgb;
  int min_slices = 6;  // a board with fewer usable slices gets no PTM (a warning says so)
};
// One PTM per board from its slices, each texel fitted under its own direction to the flash
// (per-pixel light matrices: the flash is close to the target) -> SESSION/ptm/board_BB.ptm and
// report.json.
StatusOr<StageSummary> RunPtmStage(const std::filesystem::path& session, const std::filesystem::path& layout_file,
                                   const PtmStageOptions& options, bool progress);

struct ReconstructStageOptions {
  SliceSetOptions slices;     // size: texels a side of the reconstructed slices
  std::string grid = "bonn";  // GridPairs()
  bool pixel_only = false;
  BtfMethodArgs method;
  // The settings the stage's outputs depend on: its cache key and its provenance.
  Json ToJson() const;
  // The slice set's options these ask for, or why they are invalid.
  StatusOr<SliceSetOptions> SliceOptions() const;
  // The BTF index's provenance options for `session`.
  Json Provenance(const std::filesystem::path& session) const;
};
// The slice index the stage reads, or an error saying to calibrate first.
StatusOr<std::filesystem::path> ReconstructStageIndex(const std::filesystem::path& session);
// The stage's summary from what it wrote and the BTF index's header (BtfIndexHeader).
StageSummary ReconstructStageSummary(const BtfFolderReport& written, const Json& header, const std::string& grid);
// The statistical BTF (Ngan & Durand) over a grid of direction pairs -> SESSION/btf/.
StatusOr<StageSummary> RunReconstructStage(const std::filesystem::path& session, const ReconstructStageOptions& options,
                                           bool progress);

struct SynthStageOptions {
  std::string method;  // roller | quilt; empty: no synthesis
  int width = 512, height = 512;
  uint32_t seed = 1;
  int max_slices = 289;  // slices of the BTF synthesized (those on the coarse grid first)
};
// The synth stage itself: app/synth_stage.h.

// The board whose view is closest to head-on in the slice index (the top of the pyramid).
StatusOr<int> TopBoardOfSession(const std::filesystem::path& session);
// The same of an index already read; -1 when it lists no slices.
int TopBoardOf(const SliceIndex& index);

}  // namespace mesocap::app

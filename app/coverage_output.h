// Capture guidance, shared by `mesocap coverage` (a calibrated session) and `mesocap capture
// --guide` (after each shot): the boards' measured lights scored against what the statistical
// BTF needs (reconstruct/light_coverage.h), the hemisphere plot, coverage.json and the lines the
// operator reads.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "calib/calibrate.h"
#include "core/image.h"
#include "core/json.h"
#include "core/rig_layout.h"
#include "core/status.h"
#include "reconstruct/light_coverage.h"

namespace mesocap::app {

struct CoverageAssessment {
  std::vector<BoardLights> boards;
  CoverageOptions options;  // flash_distance_m: where the flash has been held so far
  CoverageReport report;
};

// Whether a flash position leaves a board's patch free of shadows, by the rule resampling keeps
// slices by (calib/occluders.h), on a coarser grid of the patch.
LitFn ShadowFreeTest(const CalibrationResult& calibration, const RigLayout& layout);

// Whether a flash at a position (camera frame) can be used at all: calibration must find it from
// the balls (at least `min_highlights` of them show their mirror highlight lit and well inside
// their outline, HighlightOptions) and read its power from a grey card (one faces it and is not
// shadowed). Guidance suggests only such positions: from a position that fails, every board's
// slice is lost, and the next suggestion would be the same.
using FlashUsableFn = std::function<bool(const Eigen::Vector3d& position_cam)>;
FlashUsableFn FlashUsableTest(const CalibrationResult& calibration, const RigLayout& layout);

// Where guidance may suggest the flash for a board: positions `usable` allows that `lit` says light
// it. The guidance asks board by board for one position after another, so each position's
// usability is computed once (the last one is kept: not for calls from several threads).
LitFn SuggestableTest(LitFn lit, FlashUsableFn usable);

// Each posed board's lights from the flash positions (camera frame): every flash above the
// board's horizon that `lit` (when given) says lights it.
std::vector<BoardLights> BoardLightsFromFlashes(const std::vector<BoardPose>& poses, const std::vector<Eigen::Vector3d>& flashes,
                                                const LitFn& lit = nullptr);

// Scores `boards` and suggests the next flash positions at the median distance of `flashes` from
// the top board. `top_board`: the id of the most head-on board (app/rig_plot.h TopBoardPose).
CoverageAssessment AssessBoards(std::vector<BoardLights> boards, int top_board, const std::vector<Eigen::Vector3d>& flashes,
                                const CoverageOptions& options, const LitFn& lit = nullptr);

// One hemisphere per board: target directions green when covered, red when not yet, grey when no
// flash position reaches them; measured lights as white dots; the suggested next shots as rings.
Image CoveragePlot(const CoverageAssessment& assessment);

// coverage.json (docs/formats.md); `source`: where the lights came from.
Json CoverageJson(const CoverageAssessment& assessment, const std::string& source);

// coverage.json (with `extra_fields` added) and coverage.png into `out`, which appears whole
// (replacing an earlier one).
Status WriteCoverageFolder(const std::filesystem::path& out, const CoverageAssessment& assessment, const std::string& source,
                           const Json& provenance_options, const Json& extra_fields = Json::object());

// "boards also lent their lights' images under mirror_x, half_turn", or "each board's own lights
// only".
std::string HeldImagesWords(const MirrorImageSet& holds);

// "coverage: 380 of 843 ... (45%)".
std::string CoverageSummary(const CoverageAssessment& assessment);
// "  board  3:  12 lights, 40 of 62 targets covered (65%)", one line per board.
std::string BoardCoverageLines(const CoverageAssessment& assessment);
// "next 1: move the flash to the left of the camera, low, 0.95 m from the target (...): +23
// targets", one line per suggestion, or that the session is complete.
std::string NextShotLines(const CoverageAssessment& assessment);

}  // namespace mesocap::app

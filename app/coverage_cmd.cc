// mesocap coverage: capture guidance for a calibrated session (reconstruct/light_coverage.h).
// Per board, the light directions measured so far on its hemisphere, a score against what the
// statistical BTF needs, and the next flash positions that would add most, in the camera's
// frame and in words for whoever holds the flash.
#include "app/coverage_args.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "app/commands.h"
#include "app/coverage_output.h"
#include "app/rig_plot.h"
#include "app/session_stages.h"
#include "calib/calibrate.h"
#include "core/directions.h"
#include "core/json.h"
#include "core/session_layout.h"
#include "core/slice_index.h"
#include "reconstruct/light_coverage.h"
#include "reconstruct/mirror_symmetry.h"
#include "reconstruct/slice_set.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;

// Each posed board's lights: the resampled slices' (which leave out shadowed pairs) when the
// session has them, else every calibrated flash above the board's horizon that `lit` allows.
std::vector<BoardLights> MeasuredBoardLights(const CalibrationResult& calibration, const std::vector<Eigen::Vector3d>& flashes,
                                             const LitFn& lit, const fs::path& session, std::string* source) {
  const SessionLayout layout(session);
  auto index = ReadSliceIndex(layout.slices().index());
  if (!index.ok()) {
    *source = layout.Relative(layout.calibration().rig());
    return BoardLightsFromFlashes(calibration.boards, flashes, lit);
  }
  *source = layout.Relative(layout.slices().index());
  std::vector<BoardLights> boards = BoardLightsFromFlashes(calibration.boards, {});
  for (BoardLights& b : boards)
    for (const SliceIndexEntry& e : index->slices)
      if (e.board == b.board) b.lights.push_back(DirectionFromAnglesDeg(e.theta_i_deg, e.phi_i_deg));
  return boards;
}

// The images of the material its top view's slices show hold (CheckMirrorSymmetry, as
// `reconstruct` finds them), and in words; none without slices.
MirrorImageSet ImagesThatHold(const fs::path& session, std::string* words) {
  const fs::path index = SessionLayout(session).slices().index();
  *words = "no slices, so each board's own lights only";
  if (!fs::exists(index)) return {};
  SliceSetOptions options;
  options.size = 64;  // as the reconstruction's evaluation measures it; the check needs no more
  // The check reads the brightness alone: no colour noise measured against a second slice.
  options.remove_chroma_noise = false;
  // The check reads the top view alone, as the reconstruction runs it (StatisticalBtf::Create).
  SliceSetReport report;
  auto top = LoadTopView(index, options, &report);
  for (const std::string& w : report.warnings) std::fprintf(stderr, "mesocap coverage: warning: %s\n", w.c_str());
  if (!top.ok()) {
    *words = "the slices' symmetry could not be checked (" + top.status().message() + "), so each board's own lights only";
    return {};
  }
  const MirrorImageSet holds =
      CheckMirrorSymmetry(*top, options.btf.statistics.pyramid.orientations, options.btf.min_light_separation_deg).holds;
  *words = HeldImagesWords(holds);
  if (std::find(holds.begin(), holds.end(), true) == holds.end()) *words = "no image of the material holds, so " + *words;
  return holds;
}

}  // namespace

int RunCoverage(CoverageArgs a) {
  const std::string verb = "coverage";
  a.options.objective = a.objective == "near" ? CoverageObjective::kNear : CoverageObjective::kSpread;
  if (a.options.near_deg <= 0 || a.options.near_deg > 90 || a.options.suggestions < 0 || a.options.suggestions > 100)
    return Fail(verb, "--near-deg must be in (0, 90] and --suggest in [0, 100]", kExitUsage);
  const fs::path rig_file = SessionLayout(a.session).calibration().rig();
  auto loaded = LoadSessionCalibration(a.session);
  if (!loaded.ok()) return Fail(verb, loaded.status());
  const CalibrationResult& calibration = *loaded;
  const BoardPose* top = TopBoardPose(calibration);
  if (!top) return Fail(verb, rig_file.string() + ": no board was posed, so there is no hemisphere to cover");
  std::vector<Eigen::Vector3d> flashes;
  for (const ShotCalibration& shot : calibration.shots)
    if (shot.light.ok) flashes.push_back(shot.light.light_m);
  // With the rig's layout, positions that would shadow a board count nothing for it.
  // Suggested positions must also let calibration locate the flash and read its power.
  LitFn lit, suggestable;
  std::string shadows = "no layout, so shadows are not predicted";
  if (auto layout = LoadSessionLayout(a.session, a.layout_file); layout.ok()) {
    lit = ShadowFreeTest(calibration, *layout);
    suggestable = SuggestableTest(lit, FlashUsableTest(calibration, *layout));
    shadows = "shadows predicted from the layout";
  }
  std::string images = "each board's own lights only (--no-mirror-symmetry)";
  if (!a.no_mirror_symmetry) a.options.images = ImagesThatHold(a.session, &images);
  std::string source;
  const CoverageAssessment assessment =
      AssessBoards(MeasuredBoardLights(calibration, flashes, lit, a.session, &source), top->id, flashes, a.options, suggestable);
  const fs::path out = a.out.empty() ? SessionLayout(a.session).coverage().root : a.out;
  if (Status st = WriteCoverageFolder(out, assessment, source,
                                      {{"session", a.session.string()}, {"near_deg", a.options.near_deg}, {"objective", a.objective},
                                       {"suggestions", a.options.suggestions}, {"images", images}});
      !st.ok())
    return Fail(verb, st);
  std::printf("%s, lights from %s, %s; %s\n%s\n%s\n-> %s\n", CoverageSummary(assessment).c_str(), source.c_str(),
              shadows.c_str(), images.c_str(), BoardCoverageLines(assessment).c_str(), NextShotLines(assessment).c_str(),
              out.string().c_str());
  return kExitOk;
}
}  // namespace mesocap::app

// mesocap coverage: capture guidance for a calibrated session (reconstruct/light_coverage.h).
// Per board, the light directions measured so far on its hemisphere, a score against what the
// statistical BTF needs, and the next flash positions that would add most, in the camera's
// frame and in words for whoever holds the flash.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <opencv2/imgproc.hpp>

#include "app/commands.h"
#include "app/rig_plot.h"
#include "calib/calibrate.h"
#include "core/atomic_file.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "core/json.h"
#include "core/provenance.h"
#include "core/slice_index.h"
#include "core/text_format.h"
#include "reconstruct/light_coverage.h"
#include "reconstruct/statistical_btf.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;

struct CoverageArgs {
  fs::path session, out;
  CoverageOptions options;
};

// Each posed board's lights: the resampled slices' (which leave out shadowed pairs) when the
// session has them, else every calibrated flash above the board's horizon.
std::vector<BoardLights> MeasuredBoardLights(const CalibrationResult& calibration, const fs::path& session, std::string* source) {
  std::vector<BoardLights> boards;
  for (const BoardPose& pose : calibration.boards)
    if (pose.found) boards.push_back({pose.id, pose.R, pose.t, {}});
  auto index = ReadSliceIndex(session / "slices" / "index.json");
  if (index.ok()) {
    *source = "slices/index.json";
    for (BoardLights& b : boards)
      for (const SliceIndexEntry& e : index->slices)
        if (e.board == b.board) b.lights.push_back(DirectionFromAnglesDeg(e.theta_i_deg, e.phi_i_deg));
    return boards;
  }
  *source = "calibration/rig.json";
  for (BoardLights& b : boards)
    for (const ShotCalibration& shot : calibration.shots)
      if (shot.light.ok) {
        const Eigen::Vector3d light = b.LightFrom(shot.light.light_m);
        if (light.z() > 0) b.lights.push_back(light);
      }
  return boards;
}

// One hemisphere per board (orthographic: x = sin(theta) cos(phi), y = sin(theta) sin(phi)):
// target directions green when covered, red when not yet, grey when no flash position reaches
// them; measured lights as white dots; the suggested next shots as orange rings.
Image CoveragePlot(const std::vector<BoardLights>& boards, const CoverageReport& report) {
  constexpr int kPanel = 220, kColumns = 5;
  const int rows = (int(boards.size()) + kColumns - 1) / kColumns;
  Image plot(kColumns * kPanel, std::max(1, rows) * kPanel, 3, 0.04f);
  cv::Mat canvas = plot.AsMat();
  const std::vector<Eigen::Vector3d> targets = BonnDirections();
  for (int b = 0; b < int(boards.size()); ++b) {
    const cv::Point centre((b % kColumns) * kPanel + kPanel / 2, (b / kColumns) * kPanel + kPanel / 2 + 8);
    const double radius = kPanel / 2 - 22;
    auto at = [&](const Eigen::Vector3d& d) { return centre + cv::Point(int(radius * d.x()), int(-radius * d.y())); };
    cv::circle(canvas, centre, int(radius), cv::Scalar(0.3, 0.3, 0.3), 1, cv::LINE_AA);
    const BoardCoverage& bc = report.boards[b];
    cv::putText(canvas, Format("board %d: %d/%d", bc.board, bc.targets_covered, bc.targets_reachable),
                centre + cv::Point(-int(radius), -int(radius) - 6), cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(0.9, 0.9, 0.9), 1,
                cv::LINE_AA);
    for (size_t k = 0; k < targets.size(); ++k) {
      const TargetState state = bc.targets[k];
      const cv::Scalar colour = state == TargetState::kCovered     ? cv::Scalar(0.1, 0.8, 0.1)
                                : state == TargetState::kUncovered ? cv::Scalar(0.9, 0.1, 0.1)
                                                                   : cv::Scalar(0.35, 0.35, 0.35);
      cv::circle(canvas, at(targets[k]), 3, colour, cv::FILLED, cv::LINE_AA);
    }
    for (const Eigen::Vector3d& l : boards[b].lights) cv::circle(canvas, at(l), 2, cv::Scalar(1, 1, 1), cv::FILLED, cv::LINE_AA);
    for (const FlashSuggestion& s : report.next) {
      const Eigen::Vector3d l = boards[b].LightFrom(s.position_cam);
      if (l.z() > 0) cv::circle(canvas, at(l), 6, cv::Scalar(1.0, 0.55, 0.0), 2, cv::LINE_AA);
    }
  }
  return plot;
}

Json ReportJson(const CoverageReport& report, const std::string& source) {
  Json boards = Json::array();
  for (const BoardCoverage& b : report.boards)
    boards.push_back({{"board", b.board}, {"lights", b.lights}, {"targets_covered", b.targets_covered},
                      {"targets_reachable", b.targets_reachable}, {"score", b.score()}});
  Json next = Json::array();
  for (const FlashSuggestion& s : report.next)
    next.push_back({{"position_cam_m", {s.position_cam.x(), s.position_cam.y(), s.position_cam.z()}},
                    {"elevation_deg", s.elevation_deg}, {"azimuth_deg", s.azimuth_deg},
                    {"targets_gained", s.targets_gained}, {"words", s.words}});
  return {{"format", "mesocap-coverage"}, {"lights_from", source}, {"score", report.score()},
          {"covered", report.covered}, {"reachable", report.reachable}, {"boards", boards}, {"next", next}};
}

int Run(const CoverageArgs& a) {
  const std::string verb = "coverage";
  if (a.options.near_deg <= 0 || a.options.near_deg > 90 || a.options.suggestions < 0 || a.options.suggestions > 100)
    return Fail(verb, "--near-deg must be in (0, 90] and --suggest in [0, 100]", kExitUsage);
  const fs::path rig_file = a.session / "calibration" / "rig.json";
  auto rig = ReadJsonFile(rig_file);
  if (!rig.ok()) return Fail(verb, rig.status().message() + " (run `mesocap calibrate` first)");
  CalibrationResult calibration;
  try {
    calibration = CalibrationResult::FromRigJson(*rig);
  } catch (const JsonFieldError& e) {
    return Fail(verb, rig_file.string() + ": " + e.what());
  }
  const BoardPose* top = TopBoardPose(calibration);
  if (!top) return Fail(verb, rig_file.string() + ": no board was posed, so there is no hemisphere to cover");
  std::string source;
  const std::vector<BoardLights> boards = MeasuredBoardLights(calibration, a.session, &source);
  const int top_index = int(std::find_if(boards.begin(), boards.end(), [&](const BoardLights& b) { return b.board == top->id; }) -
                            boards.begin());
  // Suggestions at the distance the flash has been held at so far.
  CoverageOptions options = a.options;
  std::vector<Eigen::Vector3d> flashes;
  for (const ShotCalibration& shot : calibration.shots)
    if (shot.light.ok) flashes.push_back(shot.light.light_m);
  options.flash_distance_m = MedianFlashDistance(flashes, top->t, options.flash_distance_m);
  const CoverageReport report = AssessCoverage(boards, top_index, options);

  const fs::path out = a.out.empty() ? a.session / "coverage" : a.out;
  auto staging = StagingFolder::Begin(out);
  if (!staging.ok()) return Fail(verb, staging.status().message());
  Json json = ReportJson(report, source);
  json["provenance"] = MakeProvenance({{"session", a.session.string()}, {"near_deg", options.near_deg},
                                       {"suggestions", options.suggestions}});
  if (Status st = WriteJsonFile(staging->path() / "coverage.json", json); !st.ok()) return Fail(verb, st.message());
  if (Status st = WriteImage(staging->path() / "coverage.png", CoveragePlot(boards, report),
                             {.format = PixelFormat::kUint8Srgb});
      !st.ok())
    return Fail(verb, st.message());
  if (Status st = staging->Publish(/*replace=*/true); !st.ok()) return Fail(verb, st.message());

  std::printf("coverage: %d of %d reachable (board, light) targets within %.0f deg of a measured light (%.0f%%), lights from %s\n",
              report.covered, report.reachable, options.near_deg, 100 * report.score(), source.c_str());
  for (const BoardCoverage& b : report.boards)
    std::printf("  board %2d: %3d lights, %2d of %2d targets covered (%.0f%%)\n", b.board, b.lights, b.targets_covered,
                b.targets_reachable, 100 * b.score());
  if (report.next.empty()) std::printf("no flash position would cover more: the session is complete\n");
  for (size_t k = 0; k < report.next.size(); ++k) {
    const FlashSuggestion& s = report.next[k];
    std::printf("next %zu: move the flash %s, %.2f m from the target (camera frame %.2f, %.2f, %.2f m): +%d targets\n", k + 1,
                s.words.c_str(), options.flash_distance_m, s.position_cam.x(), s.position_cam.y(), s.position_cam.z(),
                s.targets_gained);
  }
  std::printf("-> %s\n", staging->out().string().c_str());
  return kExitOk;
}

}  // namespace

Command CoverageCommand() {
  auto args = std::make_shared<CoverageArgs>();
  Command c;
  c.name = "coverage";
  c.setup = [args](CLI::App& app) {
    CLI::App* sub = app.add_subcommand(
        "coverage",
        "Capture guidance: per board, the light directions measured so far, a score against what the BTF "
        "reconstruction needs, and the next flash positions that would add most (SESSION/coverage/)");
    sub->add_option("session", args->session, "Calibrated session folder (reads calibration/rig.json, and slices/index.json when present)")
        ->required();
    sub->add_option("--out", args->out, "Output folder (default SESSION/coverage; replaced on a re-run)");
    sub->add_option("--near-deg", args->options.near_deg, "A target light within this of a measured one is covered")
        ->capture_default_str();
    sub->add_option("--suggest", args->options.suggestions, "How many next flash positions to list")->capture_default_str();
  };
  c.run = [args]() { return Run(*args); };
  return c;
}

}  // namespace mesocap::app

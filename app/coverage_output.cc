#include "app/coverage_output.h"

#include <algorithm>
#include <map>
#include <memory>
#include <optional>
#include <opencv2/imgproc.hpp>

#include "calib/flash_lights.h"
#include "calib/occluders.h"
#include "core/atomic_file.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "core/provenance.h"
#include "core/session_layout.h"
#include "core/text_format.h"
#include "reconstruct/statistical_btf.h"

namespace mesocap::app {

namespace fs = std::filesystem;

LitFn ShadowFreeTest(const CalibrationResult& calibration, const RigLayout& layout) {
  constexpr int kGrid = 4;  // points per patch side: a shadow's edge is found within a quarter patch
  auto occluders = std::make_shared<const Occluders>(Occluders::Of(calibration, layout));
  std::map<int, std::pair<BoardPose, double>> patches;  // id -> pose, patch side
  for (const BoardPose& pose : calibration.boards)
    for (const LayoutBoard& board : layout.boards)
      if (pose.found && board.id == pose.id) patches[pose.id] = {pose, board.patch_m};
  return [occluders, patches](int board, const Eigen::Vector3d& position_cam) {
    const auto it = patches.find(board);
    if (it == patches.end()) return true;
    std::string by;
    return BlockedFraction(*occluders, it->second.first, it->second.second, kGrid, position_cam, &by) == 0;
  };
}

FlashUsableFn FlashUsableTest(const CalibrationResult& calibration, const RigLayout& layout) {
  // Margins inside calibration's own limits (a highlight up to 0.97 of the outline's radius from
  // its centre, a card lit at incidence cosine 0.15): the flash is held only near a suggestion.
  static constexpr double kHighlightReach = 0.9, kMinCardCosine = 0.3, kClearance_m = 1e-3;
  auto occluders = std::make_shared<const Occluders>(Occluders::Of(calibration, layout));
  return [occluders, balls = calibration.spheres.spheres, cards = calibration.grey_cards,
          min_highlights = HighlightOptions().min_highlights](const Eigen::Vector3d& flash) {
    int highlights = 0;
    for (const SphereEstimate& ball : balls) {
      const Eigen::Vector3d to_camera = (-ball.center_m).normalized(), to_flash = (flash - ball.center_m).normalized();
      const Eigen::Vector3d normal = (to_camera + to_flash).normalized();  // the mirror highlight's
      const double off_centre = std::sqrt(std::max(0.0, 1 - std::pow(normal.dot(to_camera), 2)));
      if (!(off_centre <= kHighlightReach)) continue;
      const Eigen::Vector3d point = ball.center_m + (ball.radius_m + kClearance_m) * normal;
      if (occluders->Blocking(point, flash, "").empty() && occluders->Blocking(point, Eigen::Vector3d::Zero(), "").empty())
        ++highlights;
    }
    if (highlights < min_highlights) return false;
    for (size_t k = 0; k < cards.size(); ++k) {
      const GreyCard& card = cards[k];
      const Eigen::Vector3d normal = card.R.col(2);
      if (normal.dot((flash - card.t).normalized()) < kMinCardCosine) continue;
      // Its grey area's corners and centre all lit: a shadow's edge across it makes it unusable.
      const std::string self = GreyCardName(int(k));
      bool lit = true;
      for (int j = -1; j <= 1 && lit; ++j)
        for (int i = -1; i <= 1 && lit; ++i) {
          const Eigen::Vector3d point = card.t + card.R * Eigen::Vector3d(i * card.size_m / 2, j * card.size_m / 2, kClearance_m);
          lit = occluders->Blocking(point, flash, self).empty();
        }
      if (lit) return true;
    }
    return cards.empty();  // no cards located: nothing to measure the power on, nothing to lose
  };
}

LitFn SuggestableTest(LitFn lit, FlashUsableFn usable) {
  auto last = std::make_shared<std::optional<std::pair<Eigen::Vector3d, bool>>>();
  return [lit = std::move(lit), usable = std::move(usable), last](int board, const Eigen::Vector3d& flash) {
    if (!*last || (*last)->first != flash) *last = std::pair{flash, usable(flash)};
    return (*last)->second && lit(board, flash);
  };
}

std::vector<BoardLights> BoardLightsFromFlashes(const std::vector<BoardPose>& poses, const std::vector<Eigen::Vector3d>& flashes,
                                                const LitFn& lit) {
  std::vector<BoardLights> boards;
  for (const BoardPose& pose : poses) {
    if (!pose.found) continue;
    BoardLights b{pose.id, pose.R, pose.t, {}};
    for (const Eigen::Vector3d& flash : flashes)
      if (const Eigen::Vector3d light = b.LightFrom(flash); light.z() > 0 && (!lit || lit(pose.id, flash)))
        b.lights.push_back(light);
    boards.push_back(std::move(b));
  }
  return boards;
}

CoverageAssessment AssessBoards(std::vector<BoardLights> boards, int top_board, const std::vector<Eigen::Vector3d>& flashes,
                                const CoverageOptions& options, const LitFn& lit) {
  CoverageAssessment a;
  a.boards = std::move(boards);
  const auto top = std::find_if(a.boards.begin(), a.boards.end(), [&](const BoardLights& b) { return b.board == top_board; });
  const int top_index = top == a.boards.end() ? 0 : int(top - a.boards.begin());
  a.options = options;
  if (!a.boards.empty())
    a.options.flash_distance_m = MedianFlashDistance(flashes, a.boards[top_index].t, options.flash_distance_m);
  a.report = AssessCoverage(a.boards, top_index, a.options, lit);
  return a;
}

Image CoveragePlot(const CoverageAssessment& assessment) {
  const std::vector<BoardLights>& boards = assessment.boards;
  const CoverageReport& report = assessment.report;
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

Json CoverageJson(const CoverageAssessment& assessment, const std::string& source) {
  const CoverageReport& report = assessment.report;
  Json boards = Json::array();
  for (const BoardCoverage& b : report.boards)
    boards.push_back({{"board", b.board}, {"lights", b.lights}, {"targets_covered", b.targets_covered},
                      {"targets_reachable", b.targets_reachable}, {"score", b.score()}});
  Json next = Json::array();
  for (const FlashSuggestion& s : report.next)
    next.push_back({{"position_cam_m", ToJson(s.position_cam)},
                    {"elevation_deg", s.elevation_deg}, {"azimuth_deg", s.azimuth_deg},
                    {"targets_gained", s.targets_gained}, {"words", s.words}});
  return {{"format", "mesocap-coverage"}, {"lights_from", source}, {"score", report.score()},
          {"covered", report.covered}, {"reachable", report.reachable}, {"boards", boards}, {"next", next}};
}

Status WriteCoverageFolder(const fs::path& out, const CoverageAssessment& assessment, const std::string& source,
                           const Json& provenance_options, const Json& extra_fields) {
  auto staging = StagingFolder::Begin(out);
  if (!staging.ok()) return staging.status();
  Json json = CoverageJson(assessment, source);
  json.update(extra_fields);
  json["provenance"] = MakeProvenance(provenance_options);
  const CoverageFolder staged{staging->path()};
  MESOCAP_RETURN_IF_ERROR(WriteJsonFile(staged.assessment(), json));
  MESOCAP_RETURN_IF_ERROR(WriteImage(staged.plot(), CoveragePlot(assessment), {.format = PixelFormat::kUint8Srgb}));
  return staging->Publish(/*replace=*/true);
}

std::string CoverageSummary(const CoverageAssessment& assessment) {
  const CoverageReport& report = assessment.report;
  return Format("coverage: %d of %d reachable (board, light) targets within %.0f deg of a measured light (%.0f%%)",
                report.covered, report.reachable, assessment.options.near_deg, 100 * report.score());
}

std::string BoardCoverageLines(const CoverageAssessment& assessment) {
  std::string text;
  for (const BoardCoverage& b : assessment.report.boards)
    text += Format("%s  board %2d: %3d lights, %2d of %2d targets covered (%.0f%%)", text.empty() ? "" : "\n", b.board,
                   b.lights, b.targets_covered, b.targets_reachable, 100 * b.score());
  return text;
}

std::string NextShotLines(const CoverageAssessment& assessment) {
  const CoverageReport& report = assessment.report;
  if (report.next.empty()) return "no flash position would cover more: the session is complete";
  std::string text;
  for (size_t k = 0; k < report.next.size(); ++k) {
    const FlashSuggestion& s = report.next[k];
    text += Format("%snext %zu: move the flash %s, %.2f m from the target (camera frame %.2f, %.2f, %.2f m): +%d targets",
                   k ? "\n" : "", k + 1, s.words.c_str(), assessment.options.flash_distance_m, s.position_cam.x(),
                   s.position_cam.y(), s.position_cam.z(), s.targets_gained);
  }
  return text;
}

std::string HeldImagesWords(const MirrorImageSet& holds) {
  std::string held;
  for (size_t k = 0; k < MirrorImages().size(); ++k)
    if (holds[k]) held += std::string(held.empty() ? "" : ", ") + MirrorImages()[k].name;
  return held.empty() ? "each board's own lights only" : "boards also lent their lights' images under " + held;
}

}  // namespace mesocap::app

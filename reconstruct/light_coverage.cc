#include "reconstruct/light_coverage.h"

#include <algorithm>
#include <cmath>

#include "core/directions.h"
#include "core/median.h"
#include "core/text_format.h"
#include "reconstruct/direction_interpolation.h"
#include "reconstruct/statistical_btf.h"

namespace mesocap {
namespace {

constexpr double kHorizonZ = 0.02;  // about 1 deg above a board's plane

// What a flash gives a board it lights: the light's angle to each of the board's targets.
struct GivenLight {
  int board = 0;
  std::vector<double> target_angles_deg;
};

// Where each board's lights also count: (board, image) pairs, the identity first (no image).
struct LightImage {
  int board = 0;
  const MirrorImage* image = nullptr;
  Eigen::Vector3d Of(const Eigen::Vector3d& light) const { return image ? image->Of(light) : light; }
};
// Each board's view: the direction to the camera in its frame.
std::vector<Eigen::Vector3d> BoardViews(const std::vector<BoardLights>& boards) {
  std::vector<Eigen::Vector3d> views;
  for (const BoardLights& b : boards) views.push_back(b.LightFrom(Eigen::Vector3d::Zero()));
  return views;
}

// A board's lights count, imaged, for the board its view's image lands on, as the reconstruction
// pools them (WithMirrorImages).
std::vector<std::vector<LightImage>> LightImages(const std::vector<BoardLights>& boards, const MirrorImageSet& use) {
  const std::vector<Eigen::Vector3d> views = BoardViews(boards);
  std::vector<std::vector<LightImage>> images(boards.size());
  for (int b = 0; b < int(boards.size()); ++b) {
    images[size_t(b)].push_back({b, nullptr});
    for (size_t k = 0; k < MirrorImages().size(); ++k) {
      if (!use[k]) continue;
      if (const int to = NearestWithin(views, MirrorImages()[k].Of(views[size_t(b)]), kMirrorPoolDeg); to >= 0)
        images[size_t(b)].push_back({to, &MirrorImages()[k]});
    }
  }
  return images;
}

// The lights a flash at `position_cam` gives the boards it lights: above a board's horizon and,
// by `lit`, with no shadow on its patch.
// (With its images, through `images`: one entry per board the light counts for.)
std::vector<GivenLight> LightsGiven(const std::vector<BoardLights>& boards, const Eigen::Vector3d& position_cam,
                                    const std::vector<Eigen::Vector3d>& targets, const LitFn& lit,
                                    const std::vector<std::vector<LightImage>>& images) {
  std::vector<GivenLight> given;
  for (int b = 0; b < int(boards.size()); ++b) {
    const Eigen::Vector3d light = boards[b].LightFrom(position_cam);
    if (light.z() <= kHorizonZ || (lit && !lit(boards[b].board, position_cam))) continue;
    for (const LightImage& image : images[size_t(b)]) {
      GivenLight g{image.board, {}};
      const Eigen::Vector3d imaged = image.Of(light);
      for (const Eigen::Vector3d& target : targets) g.target_angles_deg.push_back(AngleBetweenDeg(imaged, target));
      given.push_back(std::move(g));
    }
  }
  return given;
}

}  // namespace

double MedianFlashDistance(const std::vector<Eigen::Vector3d>& flashes, const Eigen::Vector3d& centre, double fallback) {
  if (flashes.empty()) return fallback;
  std::vector<double> distances;
  for (const Eigen::Vector3d& f : flashes) distances.push_back((f - centre).norm());
  return UpperMedian(std::move(distances));
}

std::string FlashPositionWords(const Eigen::Vector3d& position_cam, const BoardLights& top) {
  // Camera frame: x right and y down the picture. Sectors of 45 deg around the target's centre.
  const Eigen::Vector3d offset = position_cam - top.t;
  const double angle = RadToDeg(std::atan2(-offset.y(), offset.x()));  // 0 right, 90 top of the picture
  static const char* kSectors[] = {"to the right of the camera",
                                   "toward the top right of the picture",
                                   "toward the top of the picture",
                                   "toward the top left of the picture",
                                   "to the left of the camera",
                                   "toward the bottom left of the picture",
                                   "toward the bottom of the picture",
                                   "toward the bottom right of the picture"};
  const int sector = int(std::lround(std::fmod(angle + 360.0, 360.0) / 45.0)) % 8;
  const Eigen::Vector3d in_top = top.R.transpose() * offset;
  const double elevation = RadToDeg(std::asin(std::clamp(in_top.normalized().z(), -1.0, 1.0)));
  const char* height = elevation < 35 ? "low" : elevation < 60 ? "halfway up" : "high, near the camera";
  return Format("%s, %s (%.0f deg above the target's plane)", kSectors[sector], height, elevation);
}

std::vector<double> BoardWeights(const std::vector<BoardLights>& boards, bool view_blend_even_at_pole) {
  const std::vector<double> alike(boards.size(), 1.0);
  const std::vector<Eigen::Vector3d> views = BoardViews(boards);
  const StatisticalBtfOptions reconstruction;  // its view rings
  auto rings = ViewInterpolator::Create(views, reconstruction.ring_gap_deg, reconstruction.max_view_extrapolation,
                                        view_blend_even_at_pole);
  if (!rings.ok()) return alike;
  std::vector<double> weights(boards.size(), 0.0);
  double total = 0;
  for (const Eigen::Vector3d& view : BonnDirections())
    for (const WeightedIndex& w : rings->Weights(view)) weights[size_t(w.index)] += std::abs(w.weight), total += std::abs(w.weight);
  if (!(total > 0)) return alike;
  for (double& w : weights) w *= double(boards.size()) / total;
  return weights;
}

CoverageReport AssessCoverage(const std::vector<BoardLights>& boards, int top, const CoverageOptions& options,
                              const LitFn& lit) {
  CoverageReport report;
  if (boards.empty() || top < 0 || top >= int(boards.size())) return report;
  const std::vector<Eigen::Vector3d> targets = BonnDirections();
  const BoardLights& top_board = boards[top];

  // The positions considered for the next shots, and what each would cover.
  std::vector<Eigen::Vector3d> candidates;
  std::vector<std::pair<double, double>> angles;
  for (double el = options.min_elevation_deg; el <= options.max_elevation_deg + 1e-9; el += options.elevation_step_deg)
    for (double az = 0; az < 360 - 1e-9; az += options.azimuth_step_deg) {
      const Eigen::Vector3d in_top = options.flash_distance_m * DirectionFromAnglesDeg(90 - el, az);
      candidates.push_back(top_board.R * in_top + top_board.t);
      angles.push_back({el, az});
    }
  const std::vector<std::vector<LightImage>> images = LightImages(boards, options.images);
  // Each board's measured lights, with those its images lend it.
  std::vector<std::vector<Eigen::Vector3d>> measured(boards.size());
  for (int b = 0; b < int(boards.size()); ++b)
    for (const LightImage& image : images[size_t(b)])
      for (const Eigen::Vector3d& light : boards[b].lights) measured[size_t(image.board)].push_back(image.Of(light));
  std::vector<std::vector<GivenLight>> gives(candidates.size());
  std::vector<std::vector<std::pair<int, int>>> covers(candidates.size());  // (board, target)
  for (size_t c = 0; c < candidates.size(); ++c) {
    gives[c] = LightsGiven(boards, candidates[c], targets, lit, images);
    for (const GivenLight& g : gives[c])
      for (int k = 0; k < int(targets.size()); ++k)
        if (g.target_angles_deg[k] <= options.near_deg) covers[c].push_back({g.board, k});
  }

  // What is covered now, and what could be.
  std::vector<std::vector<char>> covered(boards.size(), std::vector<char>(targets.size(), 0)), reachable = covered;
  for (int b = 0; b < int(boards.size()); ++b)
    for (int k = 0; k < int(targets.size()); ++k)
      for (const Eigen::Vector3d& light : measured[size_t(b)])
        if (AngleBetweenDeg(light, targets[k]) <= options.near_deg) covered[b][k] = reachable[b][k] = 1;
  for (const auto& list : covers)
    for (const auto& [b, k] : list) reachable[b][k] = 1;
  for (int b = 0; b < int(boards.size()); ++b) {
    BoardCoverage bc;
    bc.board = boards[b].board;
    bc.lights = int(boards[b].lights.size());
    bc.targets_reachable = int(std::count(reachable[b].begin(), reachable[b].end(), 1));
    bc.targets_covered = int(std::count(covered[b].begin(), covered[b].end(), 1));
    for (size_t k = 0; k < targets.size(); ++k)
      bc.targets.push_back(covered[b][k] ? TargetState::kCovered : reachable[b][k] ? TargetState::kUncovered : TargetState::kUnreachable);
    report.reachable += bc.targets_reachable;
    report.covered += bc.targets_covered;
    report.boards.push_back(bc);
  }

  // Greedy: the position that gains most, then again with its lights taken (kSpread: each
  // target's angle to its nearest light).
  const bool spread = options.objective == CoverageObjective::kSpread;
  std::vector<std::vector<double>> nearest(boards.size(), std::vector<double>(targets.size(), options.spread_cap_deg));
  for (int b = 0; spread && b < int(boards.size()); ++b)
    for (int k = 0; k < int(targets.size()); ++k)
      for (const Eigen::Vector3d& light : measured[size_t(b)])
        nearest[b][k] = std::min(nearest[b][k], AngleBetweenDeg(light, targets[k]));
  const std::vector<double> board_weight =
      spread && options.weigh_boards_by_use ? BoardWeights(boards, options.view_blend_even_at_pole)
                                            : std::vector<double>(boards.size(), 1.0);
  const auto gain_of = [&](size_t c) {
    double gain = 0;
    if (!spread) {
      for (const auto& [b, k] : covers[c]) gain += !covered[b][k];
      return gain;
    }
    for (const GivenLight& g : gives[c])
      for (int k = 0; k < int(targets.size()); ++k)
        gain += board_weight[size_t(g.board)] * std::max(0.0, nearest[g.board][k] - g.target_angles_deg[k]);
    return gain;
  };
  for (int n = 0; n < options.suggestions; ++n) {
    int best = -1;
    double best_gain = 1e-9;
    for (size_t c = 0; c < candidates.size(); ++c)
      if (const double gain = gain_of(c); gain > best_gain) best = int(c), best_gain = gain;
    if (best < 0) break;
    FlashSuggestion s;
    for (const auto& [b, k] : covers[best]) s.targets_gained += !covered[b][k], covered[b][k] = 1;
    for (const GivenLight& g : gives[best])
      for (int k = 0; k < int(targets.size()); ++k) nearest[g.board][k] = std::min(nearest[g.board][k], g.target_angles_deg[k]);
    s.position_cam = candidates[best];
    s.elevation_deg = angles[best].first;
    s.azimuth_deg = angles[best].second;
    s.words = FlashPositionWords(s.position_cam, top_board);
    report.next.push_back(s);
  }
  return report;
}

}  // namespace mesocap

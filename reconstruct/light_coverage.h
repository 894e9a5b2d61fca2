// Capture guidance: how well a session's flash positions cover what the statistical BTF needs,
// and where the next flash shots would help most. Each board needs lights near every target
// light direction it can see (the Bonn grid's 81, in its own frame): a target more than
// `near_deg` from every measured light is extrapolated (reconstruct/statistical_btf.h), and on a
// virtual session such pairs are won half as often as covered ones (bench/session_coverage_bench).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "reconstruct/mirror_symmetry.h"

namespace mesocap {

struct BoardLights {
  int board = 0;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // X_cam = R X_board + t
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> lights;  // measured, unit, board frame
  // The unit direction to a light at `position_cam` (camera frame), in this board's frame.
  Eigen::Vector3d LightFrom(const Eigen::Vector3d& position_cam) const { return (R.transpose() * (position_cam - t)).normalized(); }
};

// The median distance of the flash positions (camera frame) from `centre`; `fallback` for none:
// where the next shots are suggested.
double MedianFlashDistance(const std::vector<Eigen::Vector3d>& flashes, const Eigen::Vector3d& centre, double fallback = 1.0);

// Whether a flash at `position_cam` (camera frame) lights board `board`'s patch with no shadow on
// it. Without one, every position above a board's horizon does.
using LitFn = std::function<bool(int board, const Eigen::Vector3d& position_cam)>;

// How the next flash positions are chosen:
//   kSpread  each shrinks most the sum over (board, target) of the angle from the target to its
//            nearest measured light, capped at `spread_cap_deg` (a farther light teaches nothing
//            about it): lights go where the measured ones are sparsest;
//   kNear    each covers most still-uncovered targets.
// On virtual sessions guided from the 6th shot to 70 (as `capture --guide` guides), kSpread's
// reconstructions are as near the truth as those from 100 hand-held shots on weave, stones and
// corduroy (bench/guidance_quality_bench.sh; docs/reconstruction.md, capture guidance); kNear's,
// from the 24th, as those from 70 (bench_session_coverage --objective near).
enum class CoverageObjective { kSpread, kNear };

struct CoverageOptions {
  CoverageObjective objective = CoverageObjective::kSpread;
  double spread_cap_deg = 30.0;
  // kSpread weighs each board's gain by how much the reconstruction of the held-out views borrows
  // from it (BoardWeights): a light for a board many views interpolate from is worth more. On
  // virtual sessions continued from 24 hand-held shots to 70 (seeds 11-20) this wins 0.9 (weave),
  // 0.4 (stones) and 0.6 (corduroy) more points of pairs beating both baselines than every board
  // alike (bench_session_coverage --guided 24 --board-weights 0|1; measured with the linear view
  // blend from the top view, whose weights were 0.50 / 1.11 / 1.01 for the top, a 30 and a 60 deg
  // board; with the default blend 0.68 / 1.07 / 1.01).
  bool weigh_boards_by_use = true;
  // The reconstruction's view blend the board weights follow (StatisticalBtfOptions).
  bool view_blend_even_at_pole = true;
  // The images of the material that hold (CheckMirrorSymmetry): a light a board measured also
  // stands, imaged, for every board its view's image lands on (within kMirrorPoolDeg), as the
  // reconstruction borrows it. None: each board's own lights only. Virtual sessions continued
  // from 24 shots to 70 (seeds 21-30, before the mean model was refitted with the images): median
  // pixel W1 0.00241 / 0.00266 / 0.00520 (weave, stones, corduroy) counting the images,
  // 0.00266 / 0.00275 / 0.00535 without; with the refit, counting them, 0.00241 / 0.00260 / 0.00514.
  MirrorImageSet images{};
  double near_deg = 15.0;  // a target within this of a measured light is covered
  // Flash positions considered for the next shots: elevations (above the top board's plane) and
  // azimuths on a sphere about the top board's centre, at `flash_distance_m`.
  double min_elevation_deg = 15, max_elevation_deg = 80, elevation_step_deg = 5, azimuth_step_deg = 10;
  double flash_distance_m = 1.0;
  int suggestions = 5;
};

enum class TargetState : uint8_t { kUnreachable, kUncovered, kCovered };

struct BoardCoverage {
  int board = 0;
  int lights = 0;
  int targets_reachable = 0;  // target directions that some considered flash position would cover
  int targets_covered = 0;    // ...within near_deg of a measured light
  std::vector<TargetState> targets;  // per BonnDirections() entry
  double score() const { return targets_reachable ? double(targets_covered) / targets_reachable : 1.0; }
};

struct FlashSuggestion {
  Eigen::Vector3d position_cam = Eigen::Vector3d::Zero();  // camera frame, metres
  double elevation_deg = 0, azimuth_deg = 0;  // in the top board's frame
  int targets_gained = 0;                     // uncovered (board, target) pairs it would cover
  std::string words;                          // "to the left of the camera, low"
};

struct CoverageReport {
  std::vector<BoardCoverage> boards;
  std::vector<FlashSuggestion> next;
  int covered = 0, reachable = 0;
  double score() const { return reachable ? double(covered) / reachable : 1.0; }
};

// Scores the boards' coverage and picks the next flash positions greedily by options.objective,
// each counting the ones before it as taken.
// `top` is the board whose frame defines elevation and azimuth (the most head-on one).
// Positions that would leave a board in shadow (`lit`) cover none of its targets.
CoverageReport AssessCoverage(const std::vector<BoardLights>& boards, int top, const CoverageOptions& options = {},
                              const LitFn& lit = nullptr);

// How much the statistical BTF's reconstruction of the held-out views (the Bonn directions)
// borrows from each board's statistics: the sum of the absolute weights its view gets in their view
// interpolation (reconstruct/direction_interpolation.h), scaled to a mean of 1 over the boards.
// Each board's view is the direction to the camera in its frame; `view_blend_even_at_pole` as the
// reconstruction's (StatisticalBtfOptions). All 1 when the views form no interpolator.
std::vector<double> BoardWeights(const std::vector<BoardLights>& boards, bool view_blend_even_at_pole = true);

// Where a flash position lies, in words for the operator holding it: seen from the camera
// (left/right, toward the top or bottom of the picture) and how high above the target.
std::string FlashPositionWords(const Eigen::Vector3d& position_cam, const BoardLights& top);

}  // namespace mesocap

// A measured slice set on disk (SESSION/slices/index.json from `mesocap calibrate`, see
// docs/formats.md) turned into the statistical BTF's inputs: one view per board, the top board's
// slices kept as base textures, every other slice reduced to its statistics as it streams by
// (memory holds one slice per thread plus the top view).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/progress.h"
#include "core/status.h"
#include "reconstruct/statistical_btf.h"

namespace mesocap {

struct SliceSetOptions {
  StatisticalBtfOptions btf;
  // Slices are area-resampled to this many texels a side (power of two; 0 keeps their size,
  // which must then be a power of two).
  int size = 0;
  // A light within this angle of one already kept for the same view is a near-duplicate and
  // skipped (Delaunay needs distinct points).
  double duplicate_light_deg = 0.5;
  // The top view (the base textures) is the most head-on board with at least 3 slices; further
  // from head-on than this and the report warns that the session has no top view.
  double max_top_view_deg = 20;
  // Whether the chromaticities come from the top view (StatisticalBtfOptions::
  // chromaticity_from_top_view, which this overrides). Unset: when the index says its shots were
  // JPEGs keeping colour at half resolution, where that wins (calibrated weave, 100 shots: 77-78%
  // of held-out pairs instead of 56-63%) and with full-resolution colour it loses.
  std::optional<bool> chroma_from_top;
  // With the chromaticity colour space, take each slice's noise out of its chromaticities'
  // statistics (RemoveNoiseVariance), the noise measured against the slice of the same view at the
  // nearest light (NoiseDifference), if within kNearHullDeg. Calibrated 100-shot JPEG sessions,
  // seeds 21-24: stones' 95th-percentile saturation off by 3.7-4.4% at the median pair instead of
  // 4.9-6.1%, corduroy's 1.3-1.5% instead of 1.6-1.8%, weave's 8.2-8.4% instead of 7.5-7.7% (its
  // slices are blurred, which this does not undo). Reads each slice twice.
  bool remove_chroma_noise = true;
  // With the chromaticity colour space, undo a Gaussian blur of this many camera pixels
  // (UndoGaussianBlur) on each session slice's chromaticities before their statistics, in texels
  // from the slice's size in the photo (SliceIndexEntry::texel_px; slices without it keep their
  // blur). The camera's pixels, its optics and the resampling's reads blur a slice; its colour is
  // what the histograms then miss, most where it varies finely. Calibrated 100-shot JPEG sessions,
  // seeds 21-24: weave's pairs beating both baselines 77.7 -> 81.3%, its 95th-percentile saturation
  // 8.2-8.4% below the truth's at the median pair -> 2.3-2.6%; stones and corduroy keep their shares
  // (held-out seed 25: weave 77.5 -> 82.1%). 0.5, 0.75 and 1.25 px did worse (docs/reconstruction.md).
  // 0: keep the blur.
  double capture_blur_px = 1.0;
  bool Check() const;
};

// A view needs lights enough to interpolate between them (a triangle); fewer and it is not used.
inline constexpr int kMinSlicesPerView = 3;

struct SliceSetReport {
  int slices_used = 0, views = 0, top_lights = 0;
  int top_board = -1;
  bool chroma_from_top = false;  // as decided (SliceSetOptions::chroma_from_top)
  std::vector<std::string> skipped;   // "file: reason"
  std::vector<std::string> warnings;  // e.g. no head-on view among the boards
  double seconds = 0;
};

// What a statistical BTF is made of: the usable views' statistics (in board order), the top
// view's slices and lights, and the options the statistics were taken with. The shards of a
// sharded reconstruction share one (reconstruct/statistics_record.h) rather than each
// recomputing it.
struct StatisticalBtfInputs {
  std::vector<MeasuredView> views;
  std::vector<Image> top_slices;
  std::vector<Eigen::Vector3d> top_lights;
  StatisticalBtfOptions btf_options;
};

// Reads the index, groups slices by board, computes statistics on all cores.
StatusOr<StatisticalBtfInputs> LoadStatisticalBtfInputs(const std::filesystem::path& index_json,
                                                        const SliceSetOptions& options, SliceSetReport* report,
                                                        const ProgressFn& progress = nullptr);
StatusOr<StatisticalBtf> CreateStatisticalBtf(StatisticalBtfInputs inputs);
// The two in one (report->seconds spans both).
StatusOr<StatisticalBtf> LoadStatisticalBtf(const std::filesystem::path& index_json, const SliceSetOptions& options,
                                            SliceSetReport* report, const ProgressFn& progress = nullptr);
// The top view's measured statistics alone, taken as LoadStatisticalBtf takes them (the colour
// basis is the top view's either way): for what needs no other board, as the symmetry check
// `mesocap coverage` runs (CheckMirrorSymmetry).
StatusOr<MeasuredView> LoadTopView(const std::filesystem::path& index_json, const SliceSetOptions& options,
                                   SliceSetReport* report = nullptr);

}  // namespace mesocap

// Patch resampling (Ngan & Durand 2006, section 2): every lit board patch of every usable shot
// becomes a rectified, undistorted texture on the texel grid of a BTF slice (docs/formats.md),
// normalised by the flash irradiance so its values are radiance per unit perpendicular
// irradiance, then rescaled so that each view's average BRDF is smooth over light directions
// (this absorbs the flash-power error the grey cards leave). Writes SESSION/slices/.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "calib/calibrate.h"
#include "core/chroma_detail.h"
#include "core/image.h"
#include "core/json.h"
#include "core/progress.h"
#include "core/rig_layout.h"
#include "core/slice_index.h"
#include "core/status.h"

namespace mesocap {

struct ResampleOptions {
  int slice_size = 512;  // texels per side
  // Sub-samples per texel axis, averaged (area filtering). 0: from the texel's footprint in the
  // photo, ceil(footprint px), so a texel larger than a pixel averages every pixel under it.
  int supersample = 0;
  bool brdf_smoothing = true;       // rescale slices to a smoothed per-view average BRDF
  // JPEG shots that keep their colour at half resolution get the colour detail restored from
  // their brightness before resampling (core/chroma_detail.h).
  bool restore_chroma_detail = true;
  double brdf_smoothing_deg = 5.0;  // Gaussian sigma on the angle between light directions
  // Shots whose grey cards were all shadowed get the session's mean power. The paper keeps
  // them and lets the BRDF smoothing correct them; by default they are skipped.
  bool keep_mean_power_shots = false;
  // Texels whose photo value reaches this (linear, any channel) count as saturated; a slice with
  // more than max_saturated_fraction of them is skipped.
  double saturation_level = 0.99;
  double max_saturated_fraction = 0.01;
  int visibility_grid = 16;  // points per patch side tested for occlusion and shadows
  int num_threads = -1;
  std::string Check() const;
  Json ToJson() const;
};

struct SliceRecord {
  std::string file;  // relative to SESSION/slices/ (index.json's folder): board_BB/shot_NNNN.exr
  int board = 0;
  std::string shot;  // the shot's file, relative to the session root
  // Light and view directions at the patch centre, patch frame (z = board normal), degrees.
  double theta_i_deg = 0, phi_i_deg = 0, theta_o_deg = 0, phi_o_deg = 0;
  double light_distance_m = 0;  // flash to patch centre
  // The patch centre's texel in the photo, pixels (sqrt of its area): how far the camera's blur
  // reaches in texels (SliceSetOptions::capture_blur_px).
  double texel_px = 0;
  // Largest angle between the centre's light direction and a patch corner's: the point light's
  // direction is not constant over the patch, while a slice carries one direction.
  double light_spread_deg = 0;
  double mean = 0;   // mean of (R+G+B)/3 over the normalised slice, before the rescale
  double scale = 1;  // the BRDF smoothing's factor (1 without smoothing)
  double saturated_fraction = 0;
  Json ToJson() const;
};

struct ResampleReport {
  int slice_size = 0;
  std::vector<int> supersample;  // per board (0 where the board was not resampled)
  std::vector<SliceRecord> slices;
  std::vector<SkippedSlice> skipped;
  double scale_min = 1, scale_max = 1, scale_rms_deviation = 0;  // over all slices: sqrt(mean (s-1)^2)
  // The shots are JPEGs that keep colour at half resolution (judged by the first slice's shot):
  // the slices' colour is blurred over two pixels (StatisticalBtfOptions::chromaticity_from_top_view).
  bool chroma_subsampled_shots = false;
  // ...and their colour detail was restored from their brightness (ResampleOptions::restore_chroma_detail).
  bool chroma_detail_restored = false;
  double seconds_total = 0;
  // Summed over threads: decoding photos, sampling and normalising, encoding and writing slices.
  double seconds_read = 0, seconds_sample = 0, seconds_write = 0;
  Json IndexJson() const;  // SESSION/slices/index.json
  std::string Brief() const;
};

// Where every sub-sample of every texel of a board's patch lands in the photo (the camera and
// the boards never move, so this is computed once per board).
struct PatchSampler {
  int board = 0;
  int size = 0;         // texels per side
  int supersample = 1;  // sub-samples per texel axis
  double patch_m = 0;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // cam_from_board
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector2f> pixels;  // texel-major, then sub-samples row by row; Image::SampleBilinear coordinates
  double footprint_px = 0;              // largest texel side seen in the photo, pixels
  double texel_px = 0;                  // the patch centre's texel, sqrt of its area in the photo, pixels
  PixelRect reach;                      // the photo's pixels the sub-samples read (unclipped)
};

// supersample = 0 chooses it from the footprint.
PatchSampler MakePatchSampler(const CameraModel& camera, const BoardPose& pose, double patch_m, int size,
                              int supersample = 0);

// One slice: the photo (linear RGB) sampled on the patch's texel grid and divided by the
// irradiance of a point flash at `light_in_board` with power x exposure `power_x_exposure`
// (pixel units, E = power cos / d^2, d from each texel centre; the cosine stays, it is part of
// the BTF). Counts texels at or above `saturation_level` in *saturated when given.
Image ResamplePatch(const Image& photo, const PatchSampler& sampler, const Eigen::Vector3d& light_in_board,
                    double power_x_exposure, double saturation_level = 0.99, int* saturated = nullptr);

// Box-filters a square image down to `size` texels a side (size must divide its side).
Image AreaDownsample(const Image& image, int size);

// Per-view smoothing of the average BRDF: mean[k] is slice k's mean, light[k] its unit light
// direction (patch frame). Smooths mean/cos(theta_i) with a Gaussian of `sigma_deg` on the angle
// between light directions and returns the factor that brings each slice to the smoothed value.
std::vector<double> BrdfSmoothingScales(const std::vector<double>& mean, const std::vector<Eigen::Vector3d>& light,
                                        double sigma_deg);

// Resamples every usable (board, shot) of a calibrated session into SESSION/slices/ and writes
// SESSION/slices/index.json (provenance included). Skips, with the reason: boards not posed or
// hidden from the camera, shots without a flash position or with a flag, lights behind a board
// (theta_i >= 90), patches shadowed by a ball, card or other board, saturated slices.
// slices/ appears whole: it is built beside the old one and swapped in at the end, after
// `also_write` (if given) has added its files to the new folder (e.g. the boards' .lp files).
using SliceFolderWriter = std::function<Status(const std::filesystem::path& slices_dir, const ResampleReport&)>;
StatusOr<ResampleReport> ResampleSession(const ResampleOptions& options, const std::filesystem::path& session,
                                         const RigLayout& layout, const CalibrationResult& calibration,
                                         const ProgressFn& progress = nullptr,
                                         const SliceFolderWriter& also_write = nullptr);

}  // namespace mesocap

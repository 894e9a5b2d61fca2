// A glTF metallic-roughness material fitted per texel to a BTF: base colour, roughness,
// metallic and a normal (core/pbr_brdf.h) minimising the squared error to the BTF's slices at
// their light and view directions. Per texel: a grid search over roughness and metallic with the
// base colour solved in closed form (the model is linear in it), then Ceres refines all seven
// parameters within their bounds. Slices are streamed in once into a texel-major table of a
// bounded number of observations (evenly spread over the index), so memory is
// texels x max_slices x 3 floats whatever the BTF's size.
#pragma once

#include <filesystem>
#include <vector>

#include <Eigen/Core>

#include "core/image.h"
#include "core/json.h"
#include "core/progress.h"
#include "core/status.h"

namespace mesocap {

struct GgxFitOptions {
  int max_slices = 300;          // observations per texel, spread evenly over the index's slices
  double max_theta_deg = 80;     // slices with a light or view further from the normal are left out
  bool fit_normals = true;       // else the normal stays the patch's
  int max_iterations = 30;       // Ceres, per texel
  int num_threads = -1;
  std::string Check() const;     // empty when valid
  Json ToJson() const;
};

struct GgxMaterialMaps {
  Image base_color;      // 3 channels, linear
  Image roughness;       // 1 channel, perceptual (alpha = roughness^2)
  Image metallic;        // 1 channel
  Image normal;          // 3 channels, unit, patch frame (x right, y up the slice, z out of the surface)
  Image relative_error;  // 1 channel: RMS residual / RMS value of the texel's observations
  int slices_used = 0;
  double median_relative_error = 0;
  double mean_iterations = 0, mean_evaluations = 0;  // Ceres's, per texel
  double seconds = 0;
  Json ToJson() const;  // the figures, not the maps
  // ToJson's figures, back (the maps stay empty); throws JsonFieldError naming the field.
  static GgxMaterialMaps FiguresFromJson(const Json& j);
};

// The fitted material's slice under a light and a view (unit directions, patch frame): what a
// glTF viewer shows of it, flat and unshadowed.
Image RelightPbrMaterial(const GgxMaterialMaps& maps, const Eigen::Vector3d& light, const Eigen::Vector3d& view);

// Fits every texel of the BTF listed in `index_json` (format mesocap-btf or mesocap-slices; with
// several boards, only `board`'s slices, -1: the first board's).
StatusOr<GgxMaterialMaps> FitGgxMaterial(const std::filesystem::path& index_json, const GgxFitOptions& options,
                                         int board = -1, const ProgressFn& progress = nullptr);

// Rows [first, last) of the BTF's texels (last -1: to the end).
struct RowBand {
  int first = 0, last = -1;
};
// The same for a band of whole rows (a shard of the fit: each row's fit runs along it from its
// first texel, so a band's texels come out as the whole fit's): maps of the band's height, their
// figures over its texels.
StatusOr<GgxMaterialMaps> FitGgxMaterialRows(const std::filesystem::path& index_json, const GgxFitOptions& options,
                                             RowBand rows, int board = -1, const ProgressFn& progress = nullptr);

// What the fit reads, decoded: the slices it uses (their directions) and, texel-major, every
// texel's observations of them (RGB), for a band of rows. FitGgxMaterialRows is the two steps
// below; a sharded fit reads the whole table once and each shard fits its band of it.
struct GgxObservations {
  int width = 0, height = 0;                    // the band's texels
  std::vector<Eigen::Vector3d> lights, views;   // per slice used, unit, patch frame
  std::vector<float> table;                     // [texel][slice][rgb]
};
StatusOr<GgxObservations> ReadGgxObservations(const std::filesystem::path& index_json, const GgxFitOptions& options,
                                              RowBand rows, int board = -1, const ProgressFn& progress = nullptr);
StatusOr<GgxMaterialMaps> FitGgxObservations(const GgxObservations& observations, const GgxFitOptions& options,
                                             const ProgressFn& progress = nullptr);

}  // namespace mesocap

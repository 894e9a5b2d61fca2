// The exemplar's appearance at a sample texel for a light and view direction in the surface's
// local frame (Tong 2002 §6), what a rendered surface point shows:
// - a BTF: the 4 measured (or reconstructed) view directions nearest the view and, for each, the
//   4 nearest light directions among that view's slices; the 4 x 4 slices' texel values blended
//   with weights w_view x w_light, each set's weights 1 / (angle + 0.01 rad) normalised to sum 1
//   (an exact slice direction all but takes the whole weight). Fewer when the BTF has fewer.
// - a PTM: the polynomial evaluated at the light (the same from every view), clamped to [0, 1]
//   as RelightPtm does.
// - an image: its colour as a Lambertian albedo, colour x cos(theta_light).
// A light below the horizon (z <= 0) gives black: an attached shadow.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/image.h"
#include "core/status.h"
#include "synth/exemplar.h"

namespace mesocap {

class SurfaceAppearance {
 public:
  // Reads a BTF's slices into memory (slices x texels x 3 floats).
  static StatusOr<SurfaceAppearance> FromExemplar(const Exemplar& exemplar, const ProgressFn& progress = nullptr);

  int width() const { return width_; }
  int height() const { return height_; }
  // Linear RGB at texel (x, y) (clamped into the sample); directions unit, local frame.
  Eigen::Vector3f Lookup(int x, int y, const Eigen::Vector3d& light, const Eigen::Vector3d& view) const;

  // The BTF blend's slices and weights for a pair of directions (empty for other kinds): what a
  // lookup sums, for tests and reports.
  struct Weighted {
    int slice;
    double weight;
  };
  std::vector<Weighted> BtfBlend(const Eigen::Vector3d& light, const Eigen::Vector3d& view) const;

 private:
  ExemplarKind kind_ = ExemplarKind::kImage;
  int width_ = 0, height_ = 0;
  Image image_;
  Ptm ptm_;
  std::vector<Image> slices_;
  // Slices grouped by view direction.
  std::vector<Eigen::Vector3d> views_;
  std::vector<int> view_indices_;  // 0, 1, ... views_.size() - 1: every view is a candidate
  std::vector<std::vector<int>> view_slices_;
  std::vector<Eigen::Vector3d> slice_lights_;
};

}  // namespace mesocap

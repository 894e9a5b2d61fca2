#include "mesh/surface_shading.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace mesocap {
namespace {

constexpr int kNearest = 4;               // views, and lights per view (Tong §6: 4 x 4 images)
constexpr double kAngleSoftening = 0.01;  // radians added to each angle before inverting

double Angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) { return std::acos(std::clamp(a.dot(b), -1.0, 1.0)); }

// The `count` nearest of `directions` (indices into it) to `d`, with normalised inverse-angle weights.
std::vector<std::pair<int, double>> NearestWeighted(const std::vector<Eigen::Vector3d>& directions,
                                                    const std::vector<int>& among, const Eigen::Vector3d& d, int count) {
  std::vector<std::pair<double, int>> by_angle;
  for (int i : among) by_angle.emplace_back(Angle(directions[i], d), i);
  const int n = std::min<int>(count, int(by_angle.size()));
  std::partial_sort(by_angle.begin(), by_angle.begin() + n, by_angle.end());
  std::vector<std::pair<int, double>> out;
  double sum = 0;
  for (int k = 0; k < n; ++k) {
    const double w = 1 / (by_angle[k].first + kAngleSoftening);
    out.emplace_back(by_angle[k].second, w), sum += w;
  }
  for (auto& [i, w] : out) w /= sum;
  return out;
}

}  // namespace

StatusOr<SurfaceAppearance> SurfaceAppearance::FromExemplar(const Exemplar& e, const ProgressFn& progress) {
  SurfaceAppearance a;
  a.kind_ = e.kind, a.width_ = e.width, a.height_ = e.height;
  if (e.kind == ExemplarKind::kImage) {
    a.image_ = e.image;
  } else if (e.kind == ExemplarKind::kPtm) {
    a.ptm_ = e.ptm;
  } else {
    for (size_t k = 0; k < e.slices.size(); ++k) {
      auto slice = e.ReadSlice(int(k));
      if (!slice.ok()) return slice.status();
      if (slice->width() != e.width || slice->height() != e.height || slice->channels() != 3)
        return Status::Error(e.slices[k].file.string() + ": not a " + std::to_string(e.width) + "x" + std::to_string(e.height) +
                             " RGB slice like the others");
      a.slices_.push_back(std::move(*slice));
      a.slice_lights_.push_back(e.slices[k].light.normalized());
      const Eigen::Vector3d view = e.slices[k].view.normalized();
      size_t v = 0;
      while (v < a.views_.size() && Angle(a.views_[v], view) > 1e-6) ++v;
      if (v == a.views_.size()) a.views_.push_back(view), a.view_slices_.emplace_back();
      a.view_slices_[v].push_back(int(k));
      if (!ReportProgress(progress, int(k + 1), int(e.slices.size()), "reading slices")) return Status::Cancelled();
    }
    if (a.slices_.empty()) return Status::Error(e.path.string() + ": the BTF has no slices");
    a.view_indices_.resize(a.views_.size());
    std::iota(a.view_indices_.begin(), a.view_indices_.end(), 0);
  }
  return a;
}

std::vector<SurfaceAppearance::Weighted> SurfaceAppearance::BtfBlend(const Eigen::Vector3d& light,
                                                                     const Eigen::Vector3d& view) const {
  std::vector<Weighted> out;
  if (kind_ != ExemplarKind::kBtf) return out;
  for (const auto& [v, wv] : NearestWeighted(views_, view_indices_, view.normalized(), kNearest))
    for (const auto& [k, wl] : NearestWeighted(slice_lights_, view_slices_[v], light.normalized(), kNearest))
      out.push_back({k, wv * wl});
  return out;
}

Eigen::Vector3f SurfaceAppearance::Lookup(int x, int y, const Eigen::Vector3d& light, const Eigen::Vector3d& view) const {
  if (!(light.z() > 0)) return Eigen::Vector3f::Zero();
  x = std::clamp(x, 0, width_ - 1), y = std::clamp(y, 0, height_ - 1);
  Eigen::Vector3f c = Eigen::Vector3f::Zero();
  if (kind_ == ExemplarKind::kImage) {
    const float* p = image_.pixel(x, y);
    const float cosine = float(light.normalized().z());
    for (int k = 0; k < 3; ++k) c[k] = p[std::min(k, image_.channels() - 1)] * cosine;
  } else if (kind_ == ExemplarKind::kPtm) {
    const Eigen::Matrix<double, 1, 6> b = PtmBasis(light.normalized());
    const float* a = ptm_.coefficients.pixel(x, y);
    for (int k = 0; k < 3; ++k) {
      const float* coef = ptm_.format == PtmFormat::kLrgb ? a : a + 6 * k;
      double v = 0;
      for (int i = 0; i < 6; ++i) v += b(i) * coef[i];
      if (ptm_.format == PtmFormat::kLrgb) v *= ptm_.rgb.at(x, y, k);
      c[k] = float(std::clamp(v, 0.0, 1.0));
    }
  } else {
    for (const Weighted& w : BtfBlend(light, view)) {
      const float* p = slices_[w.slice].pixel(x, y);
      for (int k = 0; k < 3; ++k) c[k] += float(w.weight) * p[k];
    }
  }
  return c;
}

}  // namespace mesocap

#include "reconstruct/mirror_symmetry.h"

#include <algorithm>
#include <cmath>

#include "core/directions.h"
#include "core/median.h"
#include "core/status.h"
#include "reconstruct/direction_interpolation.h"
#include "reconstruct/statistical_btf.h"

namespace mesocap {

const std::array<MirrorImage, kMirrorImageCount>& MirrorImages() {
  static const std::array<MirrorImage, kMirrorImageCount> images = {{
      {kMirrorImageNames[0], (Eigen::Matrix2d() << -1, 0, 0, 1).finished()},
      {kMirrorImageNames[1], (Eigen::Matrix2d() << 1, 0, 0, -1).finished()},
      {kMirrorImageNames[2], (Eigen::Matrix2d() << -1, 0, 0, -1).finished()},
      {kMirrorImageNames[3], (Eigen::Matrix2d() << 0, -1, 1, 0).finished()},
      {kMirrorImageNames[4], (Eigen::Matrix2d() << 0, 1, -1, 0).finished()},
      {kMirrorImageNames[5], (Eigen::Matrix2d() << 0, 1, 1, 0).finished()},
      {kMirrorImageNames[6], (Eigen::Matrix2d() << 0, -1, -1, 0).finished()},
  }};
  return images;
}

Eigen::Vector3d MirrorImage::Of(const Eigen::Vector3d& direction) const {
  const Eigen::Vector2d xy = plane * direction.head<2>();
  return {xy.x(), xy.y(), direction.z()};
}

namespace {

InverseCdf Negated(const InverseCdf& q) {
  InverseCdf out;
  out.values.assign(q.values.rbegin(), q.values.rend());
  for (float& v : out.values) v = -v;
  return out;
}

// Where imaged band `to` comes from: the source orientation and whether it is negated. The
// pyramid's frequency angle runs from f_x toward f_y down the rows, so an image of the patch frame
// (y up) acts on it as S plane S, S = diag(1, -1). Imaging the texture by a rotation through alpha
// takes band angle psi to psi + alpha, a reflection about the axis at beta to 2 beta - psi; the
// filter being cos^(K-1) of the angle from the band's, a band brought back into [0, pi) by pi is
// negated when K - 1 is odd.
std::pair<int, bool> SourceBand(const MirrorImage& image, int to, int orientations) {
  const Eigen::Matrix2d s = Eigen::Vector2d(1, -1).asDiagonal();
  const Eigen::Matrix2d a = s * image.plane * s;
  const double angle = std::atan2(a(1, 0), a(0, 0)), step = M_PI / orientations, target = to * step;
  double psi = a.determinant() > 0 ? target - angle : angle - target;
  int turns = 0;
  while (psi < -1e-9) psi += M_PI, ++turns;
  while (psi >= M_PI - 1e-9) psi -= M_PI, ++turns;
  const int from = int(std::lround(psi / step)) % orientations;
  MESOCAP_CHECK(std::abs(psi - from * step) < 1e-6 || std::abs(psi - M_PI) < 1e-6, "image does not map bands onto bands");
  return {from, turns % 2 == 1 && (orientations - 1) % 2 == 1};
}

}  // namespace

BandMap ImagedBands(const MirrorImage& image, int band_count, int orientations) {
  // bands: the high-pass residual, levels x orientations oriented bands, the low-pass residual.
  const int levels = (band_count - 2) / orientations;
  MESOCAP_CHECK(levels * orientations + 2 == band_count, "band count does not fit the orientations");
  BandMap map;
  map.from.resize(size_t(band_count));
  for (int b = 0; b < band_count; ++b) map.from[size_t(b)] = b;
  map.negated.assign(size_t(band_count), 0);
  for (int to = 0; to < orientations; ++to) {
    const auto [from, negated] = SourceBand(image, to, orientations);
    for (int l = 0; l < levels; ++l) {
      map.from[size_t(1 + l * orientations + to)] = 1 + l * orientations + from;
      map.negated[size_t(1 + l * orientations + to)] = negated;
    }
  }
  return map;
}

SliceStatistics ImagedStatistics(const SliceStatistics& statistics, const MirrorImage& image, int orientations) {
  const BandMap map = ImagedBands(image, statistics.band_count, orientations);
  SliceStatistics imaged = statistics;
  for (int c = 0; c < statistics.channels; ++c)
    for (int b = 0; b < statistics.band_count; ++b) {
      const InverseCdf& band = statistics.band(c, map.from[size_t(b)]);
      imaged.bands[size_t(c) * statistics.band_count + b] = map.negated[size_t(b)] ? Negated(band) : band;
    }
  return imaged;
}

namespace {

// Channel 0's histograms of `a` against `measured`'s: W1 over the measured one's 10-90% spread, summed.
double StatisticsDistance(const SliceStatistics& a, const SliceStatistics& measured) {
  const auto term = [](const InverseCdf& x, const InverseCdf& y) {
    return WassersteinDistance(x, y) / std::max(double(y.At(0.9) - y.At(0.1)), 1e-9);
  };
  double distance = term(a.pixels[0], measured.pixels[0]);
  for (int k = 0; k < measured.band_count; ++k) distance += term(a.band(0, k), measured.band(0, k));
  return distance;
}

// The top view's statistics of lights `indices` blended at `light` by `lights` (their
// interpolator), or empty when the nearest of them lies further than `max_gap_deg`.
SliceStatistics InterpolatedAt(const MeasuredView& top, const std::vector<int>& indices,
                               const LightInterpolator& lights, const Eigen::Vector3d& light, double max_gap_deg) {
  double nearest = 180;
  for (int i : indices) nearest = std::min(nearest, AngleBetweenDeg(top.lights[size_t(i)], light));
  if (nearest > max_gap_deg) return {};
  std::vector<const SliceStatistics*> stats;
  std::vector<double> weights;
  for (const WeightedIndex& w : lights.Weights(light)) {
    stats.push_back(&top.statistics[size_t(indices[size_t(w.index)])]);
    weights.push_back(w.weight);
  }
  return BlendSliceStatistics(stats, weights);
}

// The interpolation's own error at light i: its statistics against those blended from the others.
double LeaveOneOutDistance(const MeasuredView& top, int i, double max_gap_deg, double min_separation_deg) {
  std::vector<int> others;
  std::vector<Eigen::Vector3d> other_lights;
  for (int j = 0; j < int(top.lights.size()); ++j)
    if (j != i) others.push_back(j), other_lights.push_back(top.lights[size_t(j)]);
  auto without = LightInterpolator::Create(other_lights, min_separation_deg);
  if (!without.ok()) return 0;
  const SliceStatistics blended = InterpolatedAt(top, others, *without, top.lights[size_t(i)], max_gap_deg);
  return blended.empty() ? 0 : StatisticsDistance(blended, top.statistics[size_t(i)]);
}

// Lends `view` the light `borrowed` stands for, imaged to `light`, unless a light it has lies within
// `min_deg`.
void AddLight(const Eigen::Vector3d& light, const BorrowedSlice& borrowed, const Eigen::Vector3d* mean_rgb,
              double min_deg, MeasuredView* view) {
  for (const Eigen::Vector3d& have : view->lights)
    if (AngleBetweenDeg(have, light) < min_deg) return;
  view->lights.push_back(light);
  view->borrowed.push_back(borrowed);
  if (mean_rgb) view->mean_rgb.push_back(*mean_rgb);
}

}  // namespace

int NearestWithin(std::span<const Eigen::Vector3d> directions, const Eigen::Vector3d& direction, double within_deg) {
  int nearest = -1;
  double nearest_deg = within_deg;
  for (int i = 0; i < int(directions.size()); ++i)
    if (const double angle = AngleBetweenDeg(directions[size_t(i)], direction); angle < nearest_deg)
      nearest_deg = angle, nearest = i;
  return nearest;
}

Json MirrorSymmetryCheck::ToJson() const {
  Json j = {{"tested", tested}};
  for (size_t k = 0; k < MirrorImages().size(); ++k)
    j[MirrorImages()[k].name] = {{"holds", holds[k]},        {"allowed", allowed[k]}, {"median_ratio", ratio[k]},
                                 {"against_measured", against_measured[k]}, {"lights", lights[k]}};
  j["limit"] = kMirrorCheckLimit;
  j["tolerance"] = kMirrorCheckTolerance;
  return j;
}

MirrorSymmetryCheck CheckMirrorSymmetry(const MeasuredView& top, int orientations, double min_separation_deg,
                                        double max_gap_deg, const MirrorImageSet& allowed) {
  constexpr double kMinImageDeg = 10;
  MirrorSymmetryCheck check;
  check.allowed = allowed;
  const int n = int(top.lights.size());
  auto every = LightInterpolator::Create(top.lights, min_separation_deg);
  if (!every.ok()) return check;
  std::vector<int> all;
  for (int i = 0; i < n; ++i) all.push_back(i);
  std::array<std::vector<double>, kMirrorImageCount> ratios, as_measured;
  for (int i = 0; i < n; ++i) {
    const double own = LeaveOneOutDistance(top, i, max_gap_deg, min_separation_deg);
    if (!(own > 0)) continue;
    for (size_t k = 0; k < MirrorImages().size(); ++k) {
      const MirrorImage& image = MirrorImages()[k];
      const Eigen::Vector3d imaged = image.Of(top.lights[size_t(i)]);
      if (AngleBetweenDeg(imaged, top.lights[size_t(i)]) < kMinImageDeg) continue;
      const SliceStatistics there = InterpolatedAt(top, all, *every, imaged, max_gap_deg);
      if (there.empty()) continue;
      const SliceStatistics& measured = top.statistics[size_t(i)];
      const SliceStatistics imaged_statistics = ImagedStatistics(measured, image, orientations);
      const double imaged_distance = StatisticsDistance(there, imaged_statistics);
      const double measured_distance = std::max(StatisticsDistance(there, measured), 1e-12);
      ratios[k].push_back(imaged_distance / own);
      as_measured[k].push_back(imaged_distance / measured_distance);
    }
  }
  for (size_t k = 0; k < ratios.size(); ++k) {
    check.lights[k] = int(ratios[k].size());
    check.tested = check.tested || !ratios[k].empty();
    check.ratio[k] = UpperMedian(ratios[k]);
    check.against_measured[k] = UpperMedian(as_measured[k]);
    // The half turn only negates the bands: imaging them tells nothing of the texture's orientations.
    const bool moves_bands = !MirrorImages()[k].plane.isApprox(-Eigen::Matrix2d::Identity());
    check.holds[k] = !ratios[k].empty() && check.ratio[k] <= kMirrorCheckLimit &&
                     (!moves_bands || check.against_measured[k] <= kMirrorCheckTolerance);
  }
  if (check.holds[0] && check.holds[1]) check.holds[2] = true;  // the half turn is the mirrors' product
  for (size_t k = 0; k < check.holds.size(); ++k) check.holds[k] = check.holds[k] && allowed[k];
  return check;
}

std::vector<MeasuredView> WithMirrorImages(const std::vector<MeasuredView>& views, const MirrorImageSet& use,
                                           double pool_deg, double min_separation_deg) {
  std::vector<MeasuredView> pooled = views;
  for (size_t v = 0; v < views.size(); ++v) {
    const MeasuredView& view = views[v];
    MESOCAP_CHECK(view.borrowed.empty() && view.statistics.size() == view.lights.size(),
                  "WithMirrorImages takes measured views");
    const bool colours = view.mean_rgb.size() == view.lights.size();
    for (size_t k = 0; k < MirrorImages().size(); ++k) {
      if (!use[k]) continue;
      const MirrorImage& image = MirrorImages()[k];
      const Eigen::Vector3d imaged_view = image.Of(view.view);
      std::vector<Eigen::Vector3d> pooled_views;
      for (const MeasuredView& candidate : pooled) pooled_views.push_back(candidate.view);
      const int nearest = NearestWithin(pooled_views, imaged_view, pool_deg);
      if (nearest < 0) pooled.push_back(MeasuredView{imaged_view, {}, {}, {}, {}});
      MeasuredView* into = nearest < 0 ? &pooled.back() : &pooled[size_t(nearest)];
      // Mean colours stay only where every slice of the pooled view has one.
      const bool keep_colours = colours && into->mean_rgb.size() == into->lights.size();
      if (!keep_colours) into->mean_rgb.clear();
      for (size_t l = 0; l < view.lights.size(); ++l)
        AddLight(image.Of(view.lights[l]), BorrowedSlice{int(v), int(l), int(k)},
                 keep_colours ? &view.mean_rgb[l] : nullptr, min_separation_deg, into);
    }
  }
  return pooled;
}

}  // namespace mesocap

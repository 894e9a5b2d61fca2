#include "reconstruct/statistical_btf.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <sstream>

#include "core/directions.h"
#include "core/median.h"
#include "core/parallel.h"

namespace mesocap {

Eigen::Vector3d MeanRgb(const Image& image) {
  MESOCAP_CHECK(image.channels() == 3, "MeanRgb needs an RGB image");
  const std::vector<double> mean = ChannelMeans(image);
  return {mean[0], mean[1], mean[2]};
}

bool StatisticalBtfOptions::Check() const {
  return statistics.Check() && ring_gap_deg > 0 && min_light_separation_deg >= 0 && far_light_falloff_deg >= 0 &&
         mean_model_onset_deg > 0;
}

StatisticalBtfOptions WithColourChannels(StatisticalBtfOptions options, std::span<const Image> top_slices) {
  options.colour = ColourChannels::For(options.colour_space, top_slices);
  return options;
}

MeasuredView MeasureView(const Eigen::Vector3d& view, const std::vector<Eigen::Vector3d>& lights,
                         const std::vector<Image>& slices, const StatisticalBtfOptions& options,
                         const ProgressFn& progress) {
  MESOCAP_CHECK(lights.size() == slices.size(), "one light per slice");
  MeasuredView measured{view.normalized(), lights, std::vector<SliceStatistics>(slices.size()), {}, {}};
  if (!slices.empty() && slices.front().channels() == 3) measured.mean_rgb.resize(slices.size());
  std::atomic<int> done = 0;
  ParallelFor(0, int(slices.size()), [&](int k) {
    measured.statistics[k] = ComputeSliceStatistics(options.colour.Forward(slices[k]), options.statistics);
    if (!measured.mean_rgb.empty()) measured.mean_rgb[k] = MeanRgb(slices[k]);
    ReportProgress(progress, ++done, int(slices.size()), "statistics");
  }, options.num_threads);
  return measured;
}

namespace {

template <typename T>
std::vector<T> Flatten(const std::vector<std::vector<T>>& groups) {
  std::vector<T> all;
  for (const std::vector<T>& group : groups) all.insert(all.end(), group.begin(), group.end());
  return all;
}

// "view 3 (theta 30, phi 90 deg): ", to open a message about it.
std::string DescribeView(size_t v, const MeasuredView& view) {
  std::ostringstream where;
  const Eigen::Vector2d a = AnglesDegFromDirection(view.view);
  where << "view " << v << " (theta " << a.x() << ", phi " << a.y() << " deg): ";
  return where.str();
}

}  // namespace

StatusOr<StatisticalBtf> StatisticalBtf::Create(std::vector<Image> top_slices, std::vector<Eigen::Vector3d> top_lights,
                                                std::vector<MeasuredView> views, const StatisticalBtfOptions& options) {
  if (!options.Check()) return Status::Error("invalid statistical BTF options");
  if (top_slices.size() != top_lights.size() || top_slices.empty())
    return Status::Error("need top-view slices, one light direction each (got " + std::to_string(top_slices.size()) +
                         " slices, " + std::to_string(top_lights.size()) + " lights)");
  for (size_t k = 1; k < top_slices.size(); ++k)
    if (top_slices[k].width() != top_slices[0].width() || top_slices[k].height() != top_slices[0].height() ||
        top_slices[k].channels() != top_slices[0].channels())
      return Status::Error("top-view slice " + std::to_string(k) + " differs in size from slice 0");
  auto top = LightInterpolator::Create(top_lights, options.min_light_separation_deg);
  if (!top.ok()) return Status::Error("top view: " + top.status().message());
  if (views.empty()) return Status::Error("no measured views");
  for (size_t v = 0; v < views.size(); ++v)
    for (const SliceStatistics& s : views[v].statistics)
      if (s.band_count != views[0].statistics.front().band_count || s.channels != top_slices[0].channels())
        return Status::Error(DescribeView(v, views[v]) + "statistics of slices with a different size or channel count than the top view's");

  StatisticalBtf btf(std::move(*top));
  btf.options_ = options;
  btf.views_ = std::move(views);
  MESOCAP_RETURN_IF_ERROR(btf.IndexViews());
  if (options.fit_light_falloff) btf.light_falloff_exponent_ = btf.FitLightFalloffExponent();
  if (options.white_specular_colour && top_slices.front().channels() == 3) btf.white_lobe_ = btf.FitWhiteLobe();
  if (options.mean_model) btf.mean_model_ = btf.FitMeanModel();
  // The checks above see only what was measured (the mean model's holds each view out, which its
  // mirror images would undo); the blends, and the mean model once it has earned its use, also
  // borrow the mirror images.
  if (options.mirror_symmetry) {
    const int orientations = options.statistics.pyramid.orientations;
    btf.symmetry_check_ = CheckMirrorSymmetry(btf.views_[btf.top_view_], orientations, options.min_light_separation_deg,
                                              /*max_gap_deg=*/10, options.mirror_images_allowed);
    const auto& holds = btf.symmetry_check_.holds;
    if (std::find(holds.begin(), holds.end(), true) != holds.end()) {
      const int band_count = btf.views_[size_t(btf.top_view_)].statistics.front().band_count;  // before pooling
      btf.views_ = WithMirrorImages(btf.views_, holds, kMirrorPoolDeg, options.min_light_separation_deg);
      for (const MirrorImage& image : MirrorImages())
        btf.imaged_bands_.push_back(ImagedBands(image, band_count, orientations));
      MESOCAP_RETURN_IF_ERROR(btf.IndexViews());
      if (btf.mean_model_.fitted()) btf.mean_model_ = MeanBrightnessModel::Fit(Flatten(btf.MeanSamplesByView()));
    }
  }
  btf.top_slices_ = std::move(top_slices);
  btf.top_lights_dirs_ = top_lights;
  return btf;
}

Status StatisticalBtf::IndexViews() {
  std::vector<Eigen::Vector3d> view_dirs;
  for (const MeasuredView& v : views_) view_dirs.push_back(v.view);
  auto rings = ViewInterpolator::Create(view_dirs, options_.ring_gap_deg, options_.max_view_extrapolation,
                                        options_.view_blend_even_at_pole);
  if (!rings.ok()) return rings.status();
  view_rings_ = std::move(*rings);
  view_lights_.clear();
  for (size_t v = 0; v < views_.size(); ++v) {
    auto lights = LightInterpolator::Create(views_[v].lights, options_.min_light_separation_deg);
    if (!lights.ok()) return Status::Error(DescribeView(v, views_[v]) + lights.status().message());
    view_lights_.push_back(std::move(*lights));
  }
  top_view_ = 0;
  for (size_t v = 1; v < views_.size(); ++v)
    if (views_[v].view.z() > views_[top_view_].view.z()) top_view_ = int(v);
  return Status::Ok();
}

double StatisticalBtf::CosineRatio(const Eigen::Vector3d& target, const Eigen::Vector3d& measured) const {
  if (!options_.cosine_weighted_lights) return 1.0;
  constexpr double kMinCos = 0.1;  // about 84 deg: keeps grazing slices from being blown up
  return std::pow(std::max(target.normalized().z(), kMinCos) / std::max(measured.normalized().z(), kMinCos),
                  light_falloff_exponent_);
}

double StatisticalBtf::FitLightFalloffExponent() const {
  // Least squares of log(mean) = a + p log(cos theta_i) over the top view's lights, the mean
  // summed over the channels that scale with radiance.
  const MeasuredView& top = views_[top_view_];
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (size_t l = 0; l < top.lights.size(); ++l) {
    const double cosine = top.lights[l].normalized().z();
    const double mean = Brightness(top.statistics[l]);
    if (cosine < 0.1 || !(mean > 0)) continue;
    const double x = std::log(cosine), y = std::log(mean);
    sx += x, sy += y, sxx += x * x, sxy += x * y, ++n;
  }
  const double spread = sxx - sx * sx / std::max(n, 1);
  if (n < 3 || spread < 1e-3) return 1.0;
  return std::clamp((sxy - sx * sy / n) / spread, 0.25, 2.0);
}

double StatisticalBtf::BrightnessOf(const std::vector<double>& channel_means) const {
  // The principal axes' other two carry colour and can sum to nothing: the first is the brightness.
  if (options_.colour_space == ColourSpace::kPrincipalAxes) return channel_means[0];
  double brightness = 0;
  for (int c = 0; c < int(channel_means.size()); ++c)
    if (options_.colour.ScalesWithRadiance(c)) brightness += channel_means[size_t(c)];
  return brightness;
}

double StatisticalBtf::Brightness(const SliceStatistics& statistics) const {
  std::vector<double> means;
  for (int c = 0; c < statistics.channels; ++c) means.push_back(statistics.pixels[c].Mean());
  return BrightnessOf(means);
}

double StatisticalBtf::SliceBrightness(const Image& slice) const {
  // Every colour space's brightness channels are linear in RGB: the brightness of the mean pixel.
  const std::vector<double> means = ChannelMeans(slice);
  Image mean_pixel(1, 1, slice.channels());
  for (int c = 0; c < slice.channels(); ++c) mean_pixel.data()[c] = float(means[size_t(c)]);
  const Image channels = options_.colour.Forward(mean_pixel);
  return BrightnessOf(std::vector<double>(channels.data(), channels.data() + channels.channels()));
}

std::vector<std::vector<MeanBrightnessSample>> StatisticalBtf::MeanSamplesByView() const {
  std::vector<std::vector<MeanBrightnessSample>> by_view(views_.size());
  for (size_t v = 0; v < views_.size(); ++v)
    for (size_t l = 0; l < views_[v].lights.size(); ++l)
      by_view[v].push_back({views_[v].lights[l], views_[v].view, Brightness(SourceStatistics(int(v), l))});
  return by_view;
}

MeanBrightnessModel StatisticalBtf::FitMeanModel() {
  const std::vector<std::vector<MeanBrightnessSample>> by_view = MeanSamplesByView();
  MeanBrightnessModel model = MeanBrightnessModel::Fit(Flatten(by_view));
  if (!model.fitted()) return model;
  // Trusted only where it earns it: each tilted view's slices, predicted by the model fitted to the
  // other views, must come nearer their mean (by median log error) than the top view's at the same
  // lights, which is what far lights fall back on without it.
  std::vector<double> model_errors, top_errors;
  for (size_t v = 0; v < views_.size(); ++v) {
    if (int(v) == top_view_) continue;
    std::vector<MeanBrightnessSample> others;
    for (size_t w = 0; w < views_.size(); ++w)
      if (w != v) others.insert(others.end(), by_view[w].begin(), by_view[w].end());
    const MeanBrightnessModel without = MeanBrightnessModel::Fit(others);
    if (!without.fitted()) continue;
    for (const MeanBrightnessSample& s : by_view[v]) {
      const double predicted = without.Predict(s.light, s.view), top = TopViewBrightness(s.light);
      if (!(predicted > 0 && top > 0 && s.brightness > 0)) continue;
      model_errors.push_back(std::abs(std::log(predicted / s.brightness)));
      top_errors.push_back(std::abs(std::log(top / s.brightness)));
    }
  }
  mean_model_check_ = {UpperMedian(model_errors), UpperMedian(top_errors), int(model_errors.size()), false};
  mean_model_check_.used = !model_errors.empty() && mean_model_check_.model_error < mean_model_check_.top_view_error;
  return mean_model_check_.used ? model : MeanBrightnessModel();
}

double StatisticalBtf::TopViewBrightness(const Eigen::Vector3d& light) const {
  double brightness = 0;
  for (const WeightedIndex& w : view_lights_[top_view_].Weights(light))
    brightness += w.weight * CosineRatio(light, views_[top_view_].lights[w.index]) *
                  Brightness(SourceStatistics(top_view_, size_t(w.index)));
  return brightness;
}

double StatisticalBtf::MeanModelScale(const Image& slice, const Eigen::Vector3d& light, const Eigen::Vector3d& view) const {
  if (!mean_model_.fitted()) return 1.0;
  const double weight = 1 - std::exp(-LightGapDeg(light, view) / options_.mean_model_onset_deg);
  if (!(weight > 0)) return 1.0;  // a measured light: the blend's own mean
  // The slice as matched and clamped, not the blended statistics: matching and clamping move the mean.
  const double predicted = mean_model_.Predict(light, view), blended = SliceBrightness(slice);
  if (!(predicted > 0 && blended > 0)) return 1.0;
  // A model four times off the blend is extrapolating past what it learned: bounded there (on the
  // virtual sessions the ratio stays within 0.59-1.95, seeds 11-13).
  constexpr double kMaxLogScale = 1.3862943611198906;  // log(4)
  return std::exp(weight * std::clamp(std::log(predicted / blended), -kMaxLogScale, kMaxLogScale));
}

Json MeanModelCheck::ToJson() const {
  return {{"used", used}, {"slices", slices}, {"model_median_log_error", model_error},
          {"top_view_median_log_error", top_view_error}};
}

WhiteLobe StatisticalBtf::FitWhiteLobe() const {
  std::vector<MeanColourSample> samples;
  for (const MeasuredView& v : views_)
    if (v.mean_rgb.size() == v.lights.size())  // else the view's mean colours are unknown
      for (size_t l = 0; l < v.lights.size(); ++l) samples.push_back({v.lights[l].normalized(), v.view, v.mean_rgb[l]});
  return WhiteLobe::Fit(samples);
}

Image StatisticalBtf::BaseTexture(const Eigen::Vector3d& light) const {
  const Image& first = top_slices_.front();
  Image base(first.width(), first.height(), first.channels());
  for (const WeightedIndex& w : top_lights_.Weights(light)) {
    const float weight = float(w.weight * CosineRatio(light, top_lights_dirs_[w.index]));
    const float* src = top_slices_[w.index].data();
    float* dst = base.data();
    for (size_t i = 0; i < base.size(); ++i) dst[i] += weight * src[i];
  }
  return base;
}

SliceStatistics StatisticalBtf::TargetStatistics(const Eigen::Vector3d& light, const Eigen::Vector3d& view) const {
  const Blend blend = BlendFor(light, view);
  return BlendedStatistics(blend);
}

StatisticalBtf::Blend StatisticalBtf::BlendFor(const Eigen::Vector3d& light, const Eigen::Vector3d& view) const {
  Blend blend;
  blend.weights.resize(top_slices_.front().channels());
  for (const WeightedIndex& v : view_rings_.Weights(view)) {
    const bool inside = v.index == top_view_ || view_lights_[v.index].Contains(light);
    if (inside && v.index != top_view_ && options_.blend_change_from_top) {
      AddViewChangeFromTop(v.index, light, v.weight, &blend);
      continue;
    }
    const bool outside = options_.top_view_prior && !inside;
    const double trust = outside ? ViewChangeTrust(v.index, light) : 1.0;
    const Eigen::Vector3d edge = AddViewStatistics(v.index, light, light, trust * v.weight, &blend);
    if (!outside) continue;
    // Outside the view's hull: plus the top view at the light, minus the top view at the hull
    // edge's light the view's own statistics stand for.
    AddViewStatistics(top_view_, light, light, v.weight, &blend);
    AddViewStatistics(top_view_, edge.normalized(), light, -trust * v.weight, &blend);
  }
  if (options_.chromaticity_from_top_view) {
    const int channels = int(blend.weights.size());
    const std::vector<double> views_mean =
        options_.chromaticity_mean_from_views ? BlendedMeanChromaticity(blend) : std::vector<double>();
    for (int c = 0; c < channels; ++c)
      if (!options_.colour.ScalesWithRadiance(c)) std::fill(blend.weights[c].begin(), blend.weights[c].end(), 0.0);
    AddViewStatistics(top_view_, light, light, 1.0, &blend, ChannelSet::kChromaticity);
    if (!views_mean.empty()) {
      // The top view's histograms shifted by the views' mean chromaticity less its own.
      const std::vector<double> top_mean = BlendedMeanChromaticity(blend);
      blend.mean_shift.assign(size_t(channels), 0.0);
      for (int c = 0; c < channels; ++c) blend.mean_shift[size_t(c)] = views_mean[size_t(c)] - top_mean[size_t(c)];
    }
  }
  return blend;
}

std::vector<double> StatisticalBtf::BlendedMeanChromaticity(const Blend& blend) const {
  // The entries' chromaticities (r, g) of their mean colours, if every entry's is known.
  std::vector<std::array<float, 2>> chromaticity(blend.stats.size());
  bool from_mean_colours = true;
  for (size_t k = 0; k < blend.stats.size() && from_mean_colours; ++k) {
    const auto [v, l] = blend.measured_at[k];
    const std::vector<Eigen::Vector3d>& means = views_[size_t(v)].mean_rgb;
    float rgb[3] = {0, 0, 0};
    if (size_t(l) < means.size())
      for (int i = 0; i < 3; ++i) rgb[i] = float(means[size_t(l)][i]);
    from_mean_colours = Chromaticity(rgb, &chromaticity[k][0], &chromaticity[k][1]);
  }
  std::vector<double> mean(blend.weights.size(), 0.0);
  for (int c = 0; c < int(blend.weights.size()); ++c) {
    if (options_.colour.ScalesWithRadiance(c)) continue;
    MESOCAP_CHECK(c == 1 || c == 2, "the chromaticity channels are r (1) and g (2)");
    for (size_t k = 0; k < blend.stats.size(); ++k)
      mean[size_t(c)] += blend.weights[c][k] * (from_mean_colours ? double(chromaticity[k][size_t(c - 1)])
                                                                  : blend.stats[k]->pixels[c].Mean());
  }
  return mean;
}

SliceStatistics StatisticalBtf::BlendedStatistics(const Blend& blend) {
  SliceStatistics statistics = BlendSliceStatistics(blend.stats, blend.weights, blend.band_maps);
  for (size_t c = 0; c < blend.mean_shift.size(); ++c)
    for (float& value : statistics.pixels[c].values) value += float(blend.mean_shift[c]);
  return statistics;
}

void StatisticalBtf::AddViewChangeFromTop(int v, const Eigen::Vector3d& light, double weight, Blend* blend) const {
  AddViewStatistics(v, light, light, weight, blend);
  for (const WeightedIndex& l : view_lights_[v].Weights(light))
    AddViewStatistics(top_view_, views_[v].lights[l.index], light, -weight * l.weight, blend, ChannelSet::kRadiance);
  AddViewStatistics(top_view_, light, light, weight, blend, ChannelSet::kRadiance);
}

double StatisticalBtf::ViewChangeTrust(int v, const Eigen::Vector3d& light) const {
  if (options_.far_light_falloff_deg <= 0) return 1.0;
  return std::exp(-std::max(0.0, NearestMeasuredLightDeg(v, light) - kNearHullDeg) / options_.far_light_falloff_deg);
}

double StatisticalBtf::NearestMeasuredLightDeg(int v, const Eigen::Vector3d& light) const {
  // The nearest light by cosine, then its angle: one arc tangent, not one per light.
  const std::vector<Eigen::Vector3d>& lights = views_[size_t(v)].lights;
  const Eigen::Vector3d unit = light.normalized();
  double best_cosine = -2;
  const Eigen::Vector3d* nearest = nullptr;
  for (const Eigen::Vector3d& measured : lights)
    if (const double cosine = unit.dot(measured) / measured.norm(); cosine > best_cosine)
      best_cosine = cosine, nearest = &measured;
  return nearest ? AngleBetweenDeg(light, *nearest) : 180.0;
}

Eigen::Vector3d StatisticalBtf::AddViewStatistics(int v, const Eigen::Vector3d& at, const Eigen::Vector3d& light,
                                                  double weight, Blend* blend, ChannelSet channels) const {
  Eigen::Vector3d stands_for = Eigen::Vector3d::Zero();
  for (const WeightedIndex& l : view_lights_[v].Weights(at)) {
    stands_for += l.weight * views_[v].lights[l.index];
    blend->stats.push_back(&SourceStatistics(v, size_t(l.index)));
    blend->band_maps.push_back(SourceBandMap(v, size_t(l.index)));
    blend->measured_at.push_back({v, l.index});
    const double cosine = CosineRatio(light, views_[v].lights[l.index]);
    // A chromaticity does not scale with the light's fall-off.
    for (int c = 0; c < int(blend->weights.size()); ++c) {
      const bool radiance = options_.colour.ScalesWithRadiance(c);
      const bool weighed = channels == ChannelSet::kAll || radiance == (channels == ChannelSet::kRadiance);
      blend->weights[c].push_back(!weighed ? 0.0 : radiance ? weight * l.weight * cosine : weight * l.weight);
    }
  }
  return stands_for;
}

const SliceStatistics& StatisticalBtf::SourceStatistics(int v, size_t l) const {
  const MeasuredView& view = views_[size_t(v)];
  if (view.Measured(l)) return view.statistics[l];
  const BorrowedSlice& source = view.borrowed[l - view.statistics.size()];
  return views_[size_t(source.view)].statistics[size_t(source.light)];
}

const BandMap* StatisticalBtf::SourceBandMap(int v, size_t l) const {
  const MeasuredView& view = views_[size_t(v)];
  return view.Measured(l) ? nullptr : &imaged_bands_[size_t(view.borrowed[l - view.statistics.size()].image)];
}

bool StatisticalBtf::LightCovered(const Eigen::Vector3d& light, const Eigen::Vector3d& view) const {
  for (const WeightedIndex& v : view_rings_.Weights(view))
    if (!view_lights_[v.index].Contains(light)) return false;
  return true;
}

double StatisticalBtf::LightGapDeg(const Eigen::Vector3d& light, const Eigen::Vector3d& view) const {
  double gap = 0;
  for (const WeightedIndex& v : view_rings_.Weights(view)) gap = std::max(gap, NearestMeasuredLightDeg(v.index, light));
  return gap;
}

Image StatisticalBtf::Reconstruct(const Eigen::Vector3d& light, const Eigen::Vector3d& view) const {
  const Image base = options_.colour.Forward(BaseTexture(light));
  const Blend blend = BlendFor(light, view);
  const SliceStatistics target = BlendedStatistics(blend);
  Image matched;
  if (options_.match_subbands) {
    matched = MatchSliceStatistics(base, target, options_.statistics);
  } else {
    matched = base;
    for (int c = 0; c < matched.channels(); ++c) {
      std::vector<float> plane = ChannelPlane(matched, c);
      MatchToInverseCdf(plane, target.pixels[c]);
      SetChannelPlane(&matched, c, plane);
    }
  }
  // Statistics extrapolated beyond the outer view ring, and the way back to RGB, can leave
  // values below zero: Inverse clamps them.
  Image slice = options_.colour.Inverse(matched);
  if (const float scale = float(MeanModelScale(slice, light, view)); scale != 1.0f) {
    for (size_t i = 0; i < slice.size(); ++i) slice.data()[i] *= scale;
    ClampToStorableRadiance(&slice);
  }
  if (white_lobe_.strength() > 0 && slice.channels() == 3) MoveColourByWhiteLobe(&slice, light, view, blend);
  return slice;
}

void StatisticalBtf::MoveColourByWhiteLobe(Image* slice, const Eigen::Vector3d& light, const Eigen::Vector3d& view,
                                           const Blend& blend) const {
  // The white lobe at the pairs the statistics were measured at, weighted as their brightness is
  // blended (the first channel scales with radiance in every colour space).
  double blended = 0;
  for (size_t k = 0; k < blend.stats.size(); ++k) {
    const auto [v, l] = blend.measured_at[k];
    blended += blend.weights[0][k] * white_lobe_.Radiance(views_[v].lights[l], views_[v].view);
  }
  // Each channel's mean moves by the lobe's change, by scaling the channel, then all are scaled
  // back to the mean brightness: the colour moves toward white (or away from it), the brightness
  // stays. (Adding the change to every texel alike instead, as a uniform white reflection would,
  // lost pixel W1 on the virtual rig: stones 74.0 -> 64.6%, corduroy 67.6 -> 63.4% of pairs, on
  // the pair sample used before SpreadPairSample.)
  const double change = white_lobe_.Radiance(light, view) - blended;
  const Eigen::Vector3d mean = MeanRgb(*slice);
  const double total = mean.sum();
  if (!(total > 0)) return;
  const double keep = total / std::max(total + 3 * change, 0.25 * total);
  float scale[3];
  for (int c = 0; c < 3; ++c) scale[c] = mean[c] > 0 ? float(keep * std::max(mean[c] + change, 0.25 * mean[c]) / mean[c]) : 1.0f;
  for (size_t i = 0; i < slice->pixel_count(); ++i)
    for (int c = 0; c < 3; ++c) slice->data()[i * 3 + c] *= scale[c];
}

std::vector<Eigen::Vector3d> BonnDirections() {
  const int thetas[] = {0, 15, 30, 45, 60, 75}, counts[] = {1, 6, 12, 18, 20, 24};
  std::vector<Eigen::Vector3d> dirs;
  for (int r = 0; r < 6; ++r)
    for (int k = 0; k < counts[r]; ++k) dirs.push_back(DirectionFromAnglesDeg(thetas[r], 360.0 * k / counts[r]));
  return dirs;
}

}  // namespace mesocap

#include "synth/quilt.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <random>

#include <opencv2/imgproc.hpp>

#include "core/progress.h"
#include "core/text_format.h"
#include "synth/graphcut_fit.h"
#include "synth/patch_matching.h"
#include "synth/usage_table.h"

namespace mesocap {

int QuiltOptions::EffectiveRadius(int sample_width, int sample_height) const {
  return patch_radius > 0 ? patch_radius : std::max(min_patch_radius, std::min(32, std::min(sample_width, sample_height) / 4));
}

Status QuiltOptions::Check(int sample_width, int sample_height) const {
  if (width < 1 || height < 1 || width > 32768 || height > 32768)
    return Status::Error(Format("output size %dx%d: each side must be 1..32768 texels", width, height));
  if (min_patch_radius < 1) return Status::Error("the minimum patch radius must be at least 1");
  if (!(shrink > 0 && shrink < 1)) return Status::Error("the shrink factor must be in (0, 1)");
  if (!(seam_threshold > 0)) return Status::Error("the seam threshold must be positive");
  if (!(randomness >= 0)) return Status::Error("the randomness must be at least 0");
  if (rotations < 1 || rotations > 360) return Status::Error("rotations must be 1..360");
  if (!(usage_weight >= 0)) return Status::Error("the usage weight must be at least 0");
  if (!(usage_tolerance >= 0)) return Status::Error("the usage tolerance must be at least 0");
  const int r = EffectiveRadius(sample_width, sample_height);
  if (r < min_patch_radius) return Status::Error(Format("patch radius %d is below the minimum %d", r, min_patch_radius));
  const int smallest_copy = rotations > 1 ? int(std::min(sample_width, sample_height) / std::sqrt(2.0)) : std::min(sample_width, sample_height);
  if (2 * min_patch_radius + 1 > smallest_copy)
    return Status::Error(Format("the sample (%dx%d texels) is smaller than the smallest work patch (%d texels a side%s)",
                                sample_width, sample_height, 2 * min_patch_radius + 1, rotations > 1 ? ", rotated" : ""));
  if (patch_radius > 0 && 2 * patch_radius + 1 > std::min(sample_width, sample_height))
    return Status::Error(Format("the sample (%dx%d texels) is smaller than the work patch (%d texels a side)", sample_width,
                                sample_height, 2 * patch_radius + 1));
  return Status::Ok();
}

Image TargetConstraint(const Image& target_mask, double width) {
  cv::Mat outside(target_mask.height(), target_mask.width(), CV_8U);
  for (int y = 0; y < target_mask.height(); ++y)
    for (int x = 0; x < target_mask.width(); ++x) outside.at<uint8_t>(y, x) = target_mask.at(x, y) > 0.5f ? 0 : 255;
  cv::Mat distance;
  cv::distanceTransform(outside, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  Image m0(target_mask.width(), target_mask.height(), 1);
  for (int y = 0; y < m0.height(); ++y)
    for (int x = 0; x < m0.width(); ++x) {
      const float d = distance.at<float>(y, x);  // 0 inside F, else distance to the nearest texel of F
      m0.at(x, y) = d == 0 ? 1.f : width > 0 ? float(std::max(0.0, 1.0 - d / (width + 1))) : 0.f;
    }
  return m0;
}

namespace {

double FeatureVariance(const Image& f) {
  const int F = f.channels();
  std::vector<double> mean(F, 0);
  for (size_t t = 0; t < f.pixel_count(); ++t)
    for (int c = 0; c < F; ++c) mean[c] += f.data()[t * F + c];
  for (double& m : mean) m /= double(f.pixel_count());
  double v = 0;
  for (size_t t = 0; t < f.pixel_count(); ++t)
    for (int c = 0; c < F; ++c) v += std::pow(f.data()[t * F + c] - mean[c], 2);
  return v / double(f.pixel_count());
}

// Placements leaving the sample (QuiltOptions::whole_sample): a synthesized texel they do not
// cover costs half the mean squared step between two sample texels (as a texton slot beyond the
// sample does), and the patch's centre keeps a quarter of r_w from the sample's border. Without
// these, a patch hanging off a corner of the sample, matched on few texels, could grow a region
// of the sample's border band (a dark patch over a fifth of a stones output).
constexpr double kUncoveredShare = 0.5;
constexpr double kAnchorMargin = 0.25;
// Usage balance admits the placements within usage_tolerance x the least cost plus this share of
// 2 sigma^2: an exact continuation of the sample costs 0, and would otherwise be admitted alone.
constexpr double kNearBestFloor = 0.05;

class Quilter {
 public:
  Quilter(const Image& sample, const QuiltOptions& options, const Image* sample_mask, const Image* target,
          double match_weight, QuiltReport* report)
      : options_(options), canvas_(options.width, options.height, sample, "quilt"), rng_(options.seed), report_(*report) {
    for (int k = 0; k < options.rotations; ++k)
      copies_.push_back(MakeRotatedSample(sample, sample_mask ? *sample_mask : Image(), 360.0 * k / options.rotations));
    report_.patch_radius = options.EffectiveRadius(sample.width(), sample.height());
    PatchMatcherOptions mo;
    mo.num_threads = options.num_threads;
    mo.constraint_weight = target ? match_weight : 0;
    variance_ = FeatureVariance(sample);
    if (!target && options.whole_sample) {
      mo.max_window = 2 * report_.patch_radius + 1;
      mo.uncovered_cost = kUncoveredShare * 2 * variance_;  // 2 variance: the mean squared step between two sample texels
      mo.anchor_margin = int(kAnchorMargin * report_.patch_radius);
    }
    matcher_ = std::make_unique<PatchMatcher>(copies_, mo);
    canvas_.sample_mask = sample_mask;
    canvas_.target = target;
    report_.sample_neighbour_step = MeanNeighbourStep(sample);
    neighbours_.assign(size_t(options.width) * options.height, 0);
    unfilled_in_row_.assign(size_t(options.height), options.width);
    if (!target && options.usage_weight > 0) {  // quilting's, not painting's (whose constraint decides)
      usage_.emplace(sample.width(), sample.height());
      for (const RotatedSample& copy : copies_) {
        source_texels_.emplace_back();
        for (int v = 0; v < copy.size_y; ++v)
          for (int u = 0; u < copy.size_x; ++u) source_texels_.back().push_back(copy.SourceTexel(u, v));
      }
    }
  }

  SynthCanvas& canvas() { return canvas_; }
  const std::vector<RotatedSample>& copies() const { return copies_; }

  // Fills every texel (or, given `region`, every texel where region > 0.5) in most-constrained
  // order; returns false when cancelled.
  bool FillAll(const FitOptions& fit, const ProgressFn& progress, const Image* region = nullptr) {
    const int total = options_.width * options_.height;
    while (true) {
      const auto texel = MostConstrained(region);
      if (!texel) return true;
      PlaceAround(texel->first, texel->second, fit, /*repair=*/false);
      if (!ReportProgress(progress, filled_, total, "quilting")) return false;
    }
  }

  // Places one patch centred on (vx, vy) in a window of `radius` (0: r_w), shrunk while the cut is
  // too costly or no copy of the sample is that large; returns the number of texels it changed.
  int PlaceAround(int vx, int vy, const FitOptions& fit, bool repair, int radius = 0) {
    int r = radius > 0 ? radius : report_.patch_radius;
    double escalation = 1;  // region rule: the constraint's weight grows while no placement keeps the sides
    while (true) {
      const int x0 = std::max(0, vx - r), y0 = std::max(0, vy - r);
      const int x1 = std::min(options_.width - 1, vx + r), y1 = std::min(options_.height - 1, vy + r);
      PlacedPatch window;
      window.x0 = x0, window.y0 = y0, window.width = x1 - x0 + 1, window.height = y1 - y0 + 1;
      const MatchResult match = Match(window, vx - x0, vy - y0, escalation);
      if (!match.found) {
        MESOCAP_CHECK(r > options_.min_patch_radius, "no copy of the sample is as large as the smallest window");
        r = std::max(options_.min_patch_radius, int(r * options_.shrink));
        continue;
      }
      const PlacedPatch patch = Placed(window, match);
      CutResult cut = Cut(patch, fit);
      const bool last_try = r <= options_.min_patch_radius;
      // Under a region rule, a cut that fills no empty texel on the right side is matched again with
      // the constraint weighted more, then in smaller windows; the last try fills its empty texels
      // whatever side they land on, so every texel gets filled.
      const bool sides_kept = !region_ || KeepRegionSides(patch, &cut);
      if (!sides_kept && escalation < kMaxEscalation) {
        escalation *= 8;
        ++report_.rejected_cuts;
        continue;
      }
      if ((cut.mean_seam_cost() <= options_.seam_threshold * report_.sample_neighbour_step && sides_kept) || last_try) {
        if (cut.new_texels == 0) return 0;
        return Commit(patch, cut, repair);
      }
      ++report_.rejected_cuts;
      r = std::max(options_.min_patch_radius, int(r * options_.shrink));
    }
  }

  // The region rule (Zhou's constrained quilt: F is textured only by S_f, and here the background
  // only by S_b): while set, an empty texel inside `region` (> 0.5) takes only the sample's feature
  // texels from a patch and one outside only background texels (the rest wait for a later patch),
  // and a filled texel on the right side is never turned to the wrong one.
  void SetRegionRule(const Image* region) { region_ = region; }

  // Commits a fixed placement with a given freedom (verbatim copying).
  void PlaceFixed(const PlacedPatch& patch, const std::vector<FitFreedom>& freedom, const FitOptions& fit) {
    const CutResult cut = FitPatch(canvas_, patch, freedom, fit);
    if (cut.new_texels == 0) return;
    CommitAndCount(patch, cut);
    ++report_.patches;
  }

 private:
  static constexpr double kMaxEscalation = 512;

  // A placement whose window leaves the copy keeps only the part of the window on it.
  static void ClipToCopy(PlacedPatch* p) {
    const int left = std::max(0, -p->u0), top = std::max(0, -p->v0);
    const int right = std::min(p->width, p->copy->size_x - p->u0), bottom = std::min(p->height, p->copy->size_y - p->v0);
    p->x0 += left, p->y0 += top, p->u0 += left, p->v0 += top;
    p->width = right - left, p->height = bottom - top;
  }

  // The window's placement on the copy, clipped to the copy.
  PlacedPatch Placed(const PlacedPatch& window, const MatchResult& match) const {
    PlacedPatch patch = window;
    patch.copy = &copies_[match.rotation];
    patch.u0 = match.u, patch.v0 = match.v;
    ClipToCopy(&patch);
    return patch;
  }

  CutResult Cut(const PlacedPatch& patch, const FitOptions& fit) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<FitFreedom> freedom = DefaultFreedom(canvas_, patch);
    if (region_) KeepSatisfiedTexels(patch, &freedom);
    CutResult cut = FitPatch(canvas_, patch, freedom, fit);
    report_.seconds_cutting += SecondsSince(start);
    return cut;
  }

  int Commit(const PlacedPatch& patch, const CutResult& cut, bool repair) {
    CommitAndCount(patch, cut);
    ++report_.patches;
    if (repair) ++report_.repair_patches;
    seam_cost_sum_ += cut.seam_cost;
    seam_edges_ += cut.seam_edges;
    report_.mean_seam_cost = seam_edges_ ? seam_cost_sum_ / seam_edges_ : 0;
    return cut.new_texels;
  }

  // Commits the cut and moves the usage of the texels it replaces to the patch's source texels.
  void CommitAndCount(const PlacedPatch& patch, const CutResult& cut) {
    for (int y = 0; y < patch.height; ++y)
      for (int x = 0; x < patch.width; ++x) {
        if (!cut.take_new[size_t(y) * patch.width + x]) continue;
        const int ox = patch.x0 + x, oy = patch.y0 + y;
        const bool replaced = canvas_.synthesized[size_t(oy) * options_.width + ox];
        if (!replaced) --unfilled_in_row_[size_t(oy)], ++filled_;
        if (!usage_) continue;
        if (replaced) usage_->Add(canvas_.map.SourceTexel(ox, oy), -1);
        usage_->Add(patch.copy->SourceTexel(patch.u0 + x, patch.v0 + y), 1);
      }
    CommitPatch(&canvas_, patch, cut);
    UpdateNeighbours(patch);
  }

  // Usage balance: among the placements near the least cost, the one of least cost plus the
  // crowding of the sample around the texel under the anchor (ax, ay): the usage of the box of
  // radius r_w / 2 around it over its share under uniform use (1: used as much as the average).
  MatchResult BalancedMatch(const MatchWindow& w, int ax, int ay) {
    const double scale = options_.usage_weight * 2 * variance_;
    const int radius = std::max(1, report_.patch_radius / 2);
    const auto key = [&](const MatchResult& m) {
      const Eigen::Vector2i s = source_texels_[m.rotation][size_t(m.v + ay) * copies_[m.rotation].size_x + m.u + ax];
      return m.cost + scale * (usage_->Crowding(s, radius) - 1);
    };
    return matcher_->ChooseNearBest(w, options_.usage_tolerance, kNearBestFloor * 2 * variance_, key);
  }

  MatchWindow Window(const PlacedPatch& patch, int ax, int ay, double escalation) const {
    MatchWindow w;
    w.width = patch.width, w.height = patch.height, w.x0 = patch.x0, w.y0 = patch.y0;
    w.anchor_x = ax, w.anchor_y = ay;
    w.features = &canvas_.features;
    w.synthesized = &canvas_.synthesized;
    w.target_constraint = canvas_.target;
    w.constraint_scale = escalation;
    return w;
  }

  // (ax, ay): the window texel the patch is placed for (the most constrained one).
  MatchResult Match(const PlacedPatch& patch, int ax, int ay, double escalation) {
    const MatchWindow w = Window(patch, ax, ay, escalation);
    bool any = false;
    for (int y = 0; y < w.height && !any; ++y)
      for (int x = 0; x < w.width && !any; ++x) any = canvas_.synthesized[size_t(w.y0 + y) * options_.width + w.x0 + x];
    if (!any && !canvas_.target) {  // nothing to match yet: a random placement of the unrotated sample
      const RotatedSample& c = copies_[0];
      if (c.size_x < w.width || c.size_y < w.height) return {};
      MatchResult m;
      m.found = true;
      m.u = std::uniform_int_distribution<int>(0, c.size_x - w.width)(rng_);
      m.v = std::uniform_int_distribution<int>(0, c.size_y - w.height)(rng_);
      return m;
    }
    const auto start = std::chrono::steady_clock::now();
    const double uniform = std::uniform_real_distribution<double>(0, 1)(rng_);
    MatchResult m = usage_ && usage_->total() > 0 ? BalancedMatch(w, ax, ay)
                                           : matcher_->ChooseMatch(w, options_.randomness * variance_, uniform);
    report_.seconds_matching += SecondsSince(start);
    return m;
  }

  // Whether the patch's texel at window (x, y) is on the other side of the region's edge than the
  // output texel it covers (a feature texel outside the region, a background texel inside).
  bool NewTexelOnWrongSide(const PlacedPatch& patch, int x, int y) const {
    return (region_->at(patch.x0 + x, patch.y0 + y) > 0.5f) !=
           (patch.copy->constraint.at(patch.u0 + x, patch.v0 + y) > 0.5f);
  }

  // Drops the cut's new texels that would fill an empty texel on the wrong side of the region's edge
  // (a feature texel outside, a background texel inside); false, with the cut unchanged, when the
  // cut would fill empty texels but none on the right side.
  bool KeepRegionSides(const PlacedPatch& patch, CutResult* cut) const {
    std::vector<uint8_t> kept = cut->take_new;
    int left = 0, filled = 0, empty_taken = 0;
    for (int y = 0; y < patch.height; ++y)
      for (int x = 0; x < patch.width; ++x) {
        const size_t k = size_t(y) * patch.width + x;
        const int ox = patch.x0 + x, oy = patch.y0 + y;
        const bool empty = !canvas_.synthesized[size_t(oy) * options_.width + ox];
        empty_taken += kept[k] && empty;
        if (kept[k] && empty && NewTexelOnWrongSide(patch, x, y)) kept[k] = 0;
        left += kept[k];
        filled += kept[k] && empty;
      }
    if (filled == 0) return empty_taken == 0;  // a window over filled texels only has nothing to check
    cut->take_new = std::move(kept);
    cut->new_texels = left;
    return true;
  }

  // Filled texels on the right side of the region's edge keep their value where the patch would put
  // them on the wrong side.
  void KeepSatisfiedTexels(const PlacedPatch& patch, std::vector<FitFreedom>* freedom) const {
    for (int y = 0; y < patch.height; ++y)
      for (int x = 0; x < patch.width; ++x) {
        const int ox = patch.x0 + x, oy = patch.y0 + y;
        if (!canvas_.synthesized[size_t(oy) * options_.width + ox]) continue;
        const bool old_right = (canvas_.MaskAt(ox, oy) > 0.5f) == (region_->at(ox, oy) > 0.5f);
        if (old_right && NewTexelOnWrongSide(patch, x, y)) (*freedom)[size_t(y) * patch.width + x] = FitFreedom::kForceOld;
      }
  }

  // The unfilled texel (inside `region` if given) with the most filled neighbours, or none left.
  std::optional<std::pair<int, int>> MostConstrained(const Image* region) const {
    int best = -1, bx = 0, by = 0;
    for (int y = 0; y < options_.height; ++y) {
      if (unfilled_in_row_[size_t(y)] == 0) continue;
      for (int x = 0; x < options_.width; ++x) {
        const size_t i = size_t(y) * options_.width + x;
        if (canvas_.synthesized[i] || neighbours_[i] <= best || (region && region->at(x, y) <= 0.5f)) continue;
        best = neighbours_[i], bx = x, by = y;
        if (best == 8) return std::pair{bx, by};
      }
    }
    if (best < 0) return std::nullopt;
    if (best == 0 && canvas_.next_patch == 0)  // the very first patch: anywhere
      return std::pair{std::uniform_int_distribution<int>(0, options_.width - 1)(rng_),
                       std::uniform_int_distribution<int>(0, options_.height - 1)(rng_)};
    return std::pair{bx, by};
  }

  void UpdateNeighbours(const PlacedPatch& p) {
    const int W = options_.width, H = options_.height;
    for (int y = std::max(0, p.y0 - 1); y <= std::min(H - 1, p.y0 + p.height); ++y)
      for (int x = std::max(0, p.x0 - 1); x <= std::min(W - 1, p.x0 + p.width); ++x) {
        int n = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int ax = x + dx, ay = y + dy;
            if ((dx || dy) && ax >= 0 && ay >= 0 && ax < W && ay < H) n += canvas_.synthesized[size_t(ay) * W + ax];
          }
        neighbours_[size_t(y) * W + x] = uint8_t(n);
      }
  }

  QuiltOptions options_;
  std::vector<RotatedSample> copies_;
  std::unique_ptr<PatchMatcher> matcher_;
  SynthCanvas canvas_;
  mutable std::mt19937 rng_;
  QuiltReport& report_;
  std::vector<uint8_t> neighbours_;
  std::vector<int> unfilled_in_row_;  // the most constrained texel is looked for in these rows only
  int filled_ = 0;
  double variance_ = 0;
  std::optional<SampleUsage> usage_;  // with usage balance only
  std::vector<std::vector<Eigen::Vector2i>> source_texels_;  // likewise: per copy, per copy texel
  const Image* region_ = nullptr;
  double seam_cost_sum_ = 0;
  long seam_edges_ = 0;
};

}  // namespace

StatusOr<SynthMap> QuiltSynthesis(const Image& sample, const QuiltOptions& options, QuiltReport* report,
                                  const ProgressFn& progress, Image* built) {
  MESOCAP_RETURN_IF_ERROR(options.Check(sample.width(), sample.height()));
  const auto start = std::chrono::steady_clock::now();
  QuiltReport local;
  QuiltReport& rep = report ? *report : local;
  rep = {};
  Quilter quilter(sample, options, nullptr, nullptr, 0, &rep);
  if (!quilter.FillAll({}, progress)) return Status::Cancelled();
  rep.seconds = SecondsSince(start);
  if (built) *built = quilter.canvas().features;
  return std::move(quilter.canvas().map);
}

namespace {

// Where the feature's centroid and bounding box lie in a mask.
struct MaskRegion {
  double cx = 0, cy = 0;
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
  int count = 0;
};
MaskRegion RegionOf(const Image& mask) {
  MaskRegion r;
  r.x0 = mask.width(), r.y0 = mask.height();
  for (int y = 0; y < mask.height(); ++y)
    for (int x = 0; x < mask.width(); ++x)
      if (mask.at(x, y) > 0.5f) {
        r.cx += x, r.cy += y, ++r.count;
        r.x0 = std::min(r.x0, x), r.y0 = std::min(r.y0, y), r.x1 = std::max(r.x1, x), r.y1 = std::max(r.y1, y);
      }
  if (r.count) r.cx /= r.count, r.cy /= r.count;
  return r;
}

// The mask's 8-connected regions, largest first.
std::vector<MaskRegion> RegionsOf(const Image& mask) {
  cv::Mat inside(mask.height(), mask.width(), CV_8U);
  for (int y = 0; y < mask.height(); ++y)
    for (int x = 0; x < mask.width(); ++x) inside.at<uint8_t>(y, x) = mask.at(x, y) > 0.5f;
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(inside, labels, stats, centroids, 8, CV_32S);
  std::vector<MaskRegion> regions;
  for (int k = 1; k < n; ++k) {  // label 0 is the outside
    MaskRegion r;
    r.cx = centroids.at<double>(k, 0), r.cy = centroids.at<double>(k, 1);
    r.x0 = stats.at<int>(k, cv::CC_STAT_LEFT), r.y0 = stats.at<int>(k, cv::CC_STAT_TOP);
    r.x1 = r.x0 + stats.at<int>(k, cv::CC_STAT_WIDTH) - 1, r.y1 = r.y0 + stats.at<int>(k, cv::CC_STAT_HEIGHT) - 1;
    r.count = stats.at<int>(k, cv::CC_STAT_AREA);
    regions.push_back(r);
  }
  std::stable_sort(regions.begin(), regions.end(), [](const auto& a, const auto& b) { return a.count > b.count; });
  return regions;
}

}  // namespace

StatusOr<SynthMap> PaintSynthesis(const Image& sample, const Image& sample_mask, const Image& target_mask,
                                  const QuiltOptions& options, const PaintOptions& paint, QuiltReport* report,
                                  const ProgressFn& progress, Image* built) {
  MESOCAP_RETURN_IF_ERROR(options.Check(sample.width(), sample.height()));
  if (sample_mask.width() != sample.width() || sample_mask.height() != sample.height())
    return Status::Error(Format("the feature mask is %dx%d, the sample %dx%d", sample_mask.width(), sample_mask.height(),
                                sample.width(), sample.height()));
  if (target_mask.width() != options.width || target_mask.height() != options.height)
    return Status::Error(Format("the target mask is %dx%d, the output %dx%d", target_mask.width(), target_mask.height(),
                                options.width, options.height));
  const MaskRegion feature = RegionOf(sample_mask), target = RegionOf(target_mask);
  if (feature.count == 0) return Status::Error("the feature mask marks no texel of the sample (white = feature)");
  if (feature.count == int(sample_mask.pixel_count())) return Status::Error("the feature mask covers the whole sample: no background to quilt");
  if (target.count == 0) return Status::Error("the target mask marks no texel of the output (white = where the feature goes)");

  const auto start = std::chrono::steady_clock::now();
  QuiltReport local;
  QuiltReport& rep = report ? *report : local;
  rep = {};
  const Image m0 = TargetConstraint(target_mask, paint.transition_width);
  Image background_target(options.width, options.height, 1, 0.f);  // verbatim: quilt background first
  const double variance = FeatureVariance(sample);
  Quilter quilter(sample, options, &sample_mask, paint.verbatim ? &background_target : &m0,
                  paint.match_weight * variance, &rep);
  quilter.canvas().map.method = "paint";
  FitOptions fit;
  fit.data_weight = paint.data_weight * rep.sample_neighbour_step;
  if (!paint.verbatim) {
    // The constrained quilt Q(F) (Zhou §IV-A) comes first: each target region opens with one window
    // over it and its transition zone (as large as the sample allows), so that the joint search
    // places the feature by the constraint alone, and the rest of F grows from it; the background
    // then grows around F. Quilting the background first makes the feature's placement trade its
    // fit to m0 against the background already there (IoU 0.56-0.67 on the disk test, 0.44 on the
    // stain test, against 0.9-1.0 in this order).
    quilter.SetRegionRule(&target_mask);
    for (const MaskRegion& region : RegionsOf(target_mask)) {
      const double half_extent = 0.5 * (std::max(region.x1 - region.x0, region.y1 - region.y0) + 1);
      const int radius = std::max(rep.patch_radius, int(std::ceil(half_extent + paint.transition_width)));
      quilter.PlaceAround(int(std::lround(region.cx)), int(std::lround(region.cy)), fit, /*repair=*/false, radius);
    }
    if (!quilter.FillAll(fit, progress, &target_mask)) return Status::Cancelled();
  }
  if (!quilter.FillAll(fit, progress)) return Status::Cancelled();

  SynthCanvas& canvas = quilter.canvas();
  if (paint.verbatim) {
    // Paste the feature's bounding box (plus the transition zone) with its centroid on the target's.
    canvas.target = &m0;
    const int margin = int(std::ceil(paint.transition_width)) + 2;
    const int dx = int(std::lround(target.cx - feature.cx)), dy = int(std::lround(target.cy - feature.cy));
    PlacedPatch patch;
    patch.copy = &quilter.copies()[0];
    const int sx0 = std::max(0, feature.x0 - margin), sy0 = std::max(0, feature.y0 - margin);
    const int sx1 = std::min(sample.width() - 1, feature.x1 + margin), sy1 = std::min(sample.height() - 1, feature.y1 + margin);
    patch.x0 = std::max(0, sx0 + dx), patch.y0 = std::max(0, sy0 + dy);
    const int ox1 = std::min(options.width - 1, sx1 + dx), oy1 = std::min(options.height - 1, sy1 + dy);
    if (ox1 < patch.x0 || oy1 < patch.y0) return Status::Error("the target mask places the feature outside the output");
    patch.width = ox1 - patch.x0 + 1, patch.height = oy1 - patch.y0 + 1;
    patch.u0 = patch.x0 - dx, patch.v0 = patch.y0 - dy;
    std::vector<FitFreedom> freedom = DefaultFreedom(canvas, patch);
    for (int y = 0; y < patch.height; ++y)
      for (int x = 0; x < patch.width; ++x)
        if (sample_mask.at(patch.u0 + x, patch.v0 + y) > 0.5f) freedom[size_t(y) * patch.width + x] = FitFreedom::kForceNew;
    quilter.PlaceFixed(patch, freedom, fit);
  } else {
    // Repair: patches centred on texels whose feature label still disagrees with m0.
    std::vector<uint8_t> given_up(size_t(options.width) * options.height, 0);
    for (int k = 0; k < paint.max_repair_patches; ++k) {
      int vx = -1, vy = -1;
      for (int y = 0; y < options.height && vx < 0; ++y)
        for (int x = 0; x < options.width && vx < 0; ++x)
          if (!given_up[size_t(y) * options.width + x] && std::abs(canvas.MaskAt(x, y) - m0.at(x, y)) > 0.5f) vx = x, vy = y;
      if (vx < 0) break;
      if (quilter.PlaceAround(vx, vy, fit, /*repair=*/true) == 0 || std::abs(canvas.MaskAt(vx, vy) - m0.at(vx, vy)) > 0.5f)
        given_up[size_t(vy) * options.width + vx] = 1;
    }
  }
  rep.seconds = SecondsSince(start);
  if (built) *built = canvas.features;
  return std::move(canvas.map);
}

}  // namespace mesocap

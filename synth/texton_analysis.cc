#include "synth/texton_analysis.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <string>

#include "core/image_io.h"
#include "core/parallel.h"
#include "synth/exemplar.h"
#include "synth/filter_bank.h"
#include "synth/kmeans.h"
#include "synth/separable_filter.h"

namespace mesocap {
namespace {

// The coarsest level's spacing leaves at least this many steps a side. Levels up to where the
// sample spans 3 steps, not 8 as before, carry the structure of bricks and bark to the output: on
// the 20 photographs the subband ratio to random tiling went 1.31x -> 0.93x (geometric mean, one
// seed), textures at or below random tiling 6 -> 13, seams at most 1.41 -> 1.19
// (docs/synthesis.md).
constexpr int kMinLevelSpan = 3;
constexpr int kMinTextons = 16;    // coarse levels keep at least this many textons (a quarter per level otherwise)

// Stack levels for a sample: spacing 2^l, while the shorter side spans at least kMinLevelSpan
// steps of the coarsest spacing (the finest always counts); `wanted` 0 means as many as fit.
int UsableLevels(int width, int height, int wanted) {
  const int side = std::min(width, height);
  int levels = 1;
  while ((wanted == 0 || levels < wanted) && levels < kMaxTextonLevels && side / (1 << levels) >= kMinLevelSpan) ++levels;
  return levels;
}

// Level l of the Gaussian stack of per-texel features: every channel blurred by a Gaussian of the
// width a pyramid reaches after l reductions (sigma^2 = (4^l - 1) / 3 of the 5-tap binomial), the
// border mirrored. Blurring the filter responses equals filtering the blurred slices.
Image StackLevel(const Image& features, int level, int num_threads) {
  if (level == 0) return features;
  const double sigma = std::sqrt((std::pow(4.0, level) - 1) / 3);
  const int radius = int(std::ceil(3 * sigma));
  std::vector<float> kernel(2 * radius + 1);
  double sum = 0;
  for (int i = -radius; i <= radius; ++i) sum += kernel[i + radius] = float(std::exp(-0.5 * i * i / (sigma * sigma)));
  for (float& k : kernel) k = float(k / sum);
  return SeparableFilter(features, kernel, 1, num_threads);
}

// The filter responses followed by the slice's own values over the texel's 3 x 3 neighbourhood
// (mirrored at the border), times `weight`: the filters' smallest scale is sqrt(2) texels, so
// responses alone hardly tell adjacent texels apart, and a synthesis matched on them stretches
// single texels and loses fine grain (after Lefebvre & Hoppe 2006's appearance space, whose
// vectors are the texel's neighbourhood).
Image WithTexelValues(const Image& responses, const Image& slice, double weight) {
  if (weight <= 0) return responses;
  const int W = slice.width(), H = slice.height(), R = responses.channels();
  Image out(W, H, R + 9);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      float* o = out.pixel(x, y);
      std::copy_n(responses.pixel(x, y), R, o);
      for (int j = 0; j < 9; ++j) {
        o[R + j] = float(weight) * slice.at(MirrorIndex101(x + j % 3 - 1, W), MirrorIndex101(y + j / 3 - 1, H));
      }
    }
  return out;
}

// A slice's image appearance vector: its responses on a regular grid of about `points` texels.
Eigen::VectorXd AppearanceVector(const Image& responses, int points) {
  const int step = std::max(1, int(std::sqrt(double(responses.pixel_count()) / std::max(1, points))));
  std::vector<double> v;
  for (int y = step / 2; y < responses.height(); y += step)
    for (int x = step / 2; x < responses.width(); x += step)
      for (int k = 0; k < responses.channels(); ++k) v.push_back(responses.at(x, y, k));
  return Eigen::Map<Eigen::VectorXd>(v.data(), Eigen::Index(v.size()));
}

// n_s representative slices: K-means over the slices' appearance vectors, the member nearest
// each centre (Tong §4). All slices when there are no more than n_s.
StatusOr<std::vector<int>> RepresentativeSlices(int count, const std::function<StatusOr<Image>(int)>& slice,
                                                const FilterBank& bank, const TextonAnalysisOptions& o,
                                                const ProgressFn& progress) {
  std::vector<int> all(count);
  std::iota(all.begin(), all.end(), 0);
  if (count <= o.representative_slices) return all;
  std::vector<Eigen::VectorXd> vectors(count);
  std::vector<Status> errors(count, Status::Ok());
  ParallelFor(0, count, [&](int k) {
    auto s = slice(k);
    if (!s.ok()) return void(errors[k] = s.status());
    vectors[k] = AppearanceVector(bank.Responses(*s), o.grid_points);
  }, o.num_threads);
  for (const Status& st : errors) MESOCAP_RETURN_IF_ERROR(st);
  if (!ReportProgress(progress, 1, 1, "representative slices")) return Status::Cancelled();
  Eigen::MatrixXd points(count, vectors[0].size());
  for (int k = 0; k < count; ++k) points.row(k) = vectors[k].transpose();
  const KMeansResult clusters = KMeans(points, {o.representative_slices, o.kmeans_iterations, o.seed, o.num_threads});
  std::vector<int> nearest(clusters.centres.rows(), -1);
  std::vector<double> best(clusters.centres.rows(), 0);
  for (int k = 0; k < count; ++k) {
    const int c = clusters.labels[k];
    const double d = (points.row(k) - clusters.centres.row(c)).squaredNorm();
    if (nearest[c] < 0 || d < best[c]) nearest[c] = k, best[c] = d;
  }
  std::vector<int> chosen;
  for (int k : nearest)
    if (k >= 0) chosen.push_back(k);
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

}  // namespace

Status TextonAnalysisOptions::Check() const {
  if (representative_slices < 1) return Status::Error("the representative slices n_s must be at least 1");
  if (textons < 1 || textons > 65534) return Status::Error("the textons n_t must be 1..65534");
  if (levels < 0 || levels > kMaxTextonLevels)
    return Status::Error("the stack levels must be 0..8 (0: as many as the sample holds)");
  if (grid_points < 1) return Status::Error("the grid points must be at least 1");
  if (dimensions < 1) return Status::Error("the dimensions must be at least 1");
  if (kmeans_iterations < 1) return Status::Error("the K-means iterations must be at least 1");
  return Status::Ok();
}

StatusOr<TextonAnalysis> AnalyzeTextons(int slice_count, const std::function<StatusOr<Image>(int)>& read_luminance,
                                        const TextonAnalysisOptions& o, const ProgressFn& progress,
                                        std::vector<TextonVocabulary>* vocabulary) {
  MESOCAP_RETURN_IF_ERROR(o.Check());
  if (slice_count < 1) return Status::Error("texton analysis of a sample without slices");
  const auto start = std::chrono::steady_clock::now();
  auto first = read_luminance(0);
  if (!first.ok()) return first.status();
  const int width = first->width(), height = first->height();
  if (first->channels() != 1) return Status::Error("texton analysis needs one-channel (luminance) slices");
  auto slice_at = [&](int k) -> StatusOr<Image> {
    auto s = read_luminance(k);
    if (!s.ok()) return s.status();
    if (s->width() != width || s->height() != height || s->channels() != 1)
      return Status::Error("slice " + std::to_string(k) + " is " + std::to_string(s->width()) + "x" +
                           std::to_string(s->height()) + ", slice 0 is " + std::to_string(width) + "x" + std::to_string(height));
    // Each slice divided by its RMS value: every light and view weighs the same in the clustering.
    // (The filters' responses are not equalised: giving the edge filters the Gaussians' weight
    // made the syntheses' subband statistics 1.8-2.4x worse on the virtual-rig weave and stones.)
    return DividedByRms(std::move(*s));
  };

  TextonAnalysis analysis;
  analysis.slice_count = slice_count;
  const int levels = UsableLevels(width, height, o.levels);
  const FilterBank bank(width, height);
  auto chosen = RepresentativeSlices(slice_count, slice_at, bank, o, progress);
  if (!chosen.ok()) return chosen.status();
  analysis.representative_slices = *chosen;
  const int ns = int(chosen->size());

  // The finest level's texel vectors: the representative slices' filter responses, projected.
  auto finest = GeometryMapsOfSlices(
      ns, [&](int i) -> StatusOr<Image> {
        auto s = slice_at((*chosen)[i]);
        if (!s.ok()) return s.status();
        return WithTexelValues(bank.Responses(*s), *s, o.texel_value_weight);
      },
      o.dimensions, 1, /*normalize=*/false, o.num_threads,
      [&](int done, int total, const std::string&) { return ReportProgress(progress, done, total, "filter responses"); });
  if (!finest.ok()) return finest.status();

  for (int l = 0; l < levels; ++l) {
    const std::string what = "textons, level " + std::to_string(l);
    Image vectors = StackLevel(finest->features, l, o.num_threads);
    const Eigen::MatrixXd points = TexelMatrix(vectors).cast<double>();
    // A quarter of the textons per coarser level (Tong §5.1), but no fewer than kMinTextons: a
    // stack level keeps every texel, and its blurred structure still needs telling apart.
    const int wanted = std::max({1, o.textons >> (2 * l), std::min(o.textons, kMinTextons)});
    const KMeansResult clusters = KMeans(points, {wanted, o.kmeans_iterations, o.seed + uint32_t(l), o.num_threads});
    TextonLevel level;
    level.width = width, level.height = height, level.spacing = 1 << l;
    level.textons = int(clusters.centres.rows());
    level.labels.assign(clusters.labels.begin(), clusters.labels.end());
    Eigen::MatrixXd with_default(level.textons + 1, points.cols());
    with_default.topRows(level.textons) = clusters.centres;
    with_default.row(level.textons) = clusters.centres.colwise().mean();
    level.gamma = with_default * with_default.transpose();
    // Exactly symmetric, and in float precision, as textons.exr stores it: a run reusing the saved
    // analysis finds the same map as the run that made it.
    level.gamma = (0.5 * (level.gamma + level.gamma.transpose())).cast<float>().cast<double>();
    level.energy_kept = finest->energy_kept;
    analysis.levels.push_back(std::move(level));
    if (vocabulary) vocabulary->push_back({std::move(vectors), clusters.centres});
    if (!ReportProgress(progress, l + 1, levels, what)) return Status::Cancelled();
  }
  analysis.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return analysis;
}

int LevelsSpanning(const TextonAnalysis& analysis, int min_steps) {
  int levels = 0;
  for (const TextonLevel& level : analysis.levels)
    if (levels == 0 || std::min(level.width, level.height) / level.spacing >= min_steps) ++levels;
  return levels;
}

std::vector<float> TextonDistances(const TextonLevel& level) {
  const int n = level.textons + 1;
  std::vector<float> d(size_t(n) * n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      d[size_t(i) * n + j] = float(std::max(0.0, level.gamma(i, i) + level.gamma(j, j) - 2 * level.gamma(i, j)));
  return d;
}

namespace {

constexpr const char* kQuantity = "texton analysis (Tong et al. 2002)";
constexpr const char* kLayout = "gaussian-stack";  // every level at the sample's size

std::string JoinInts(const std::vector<int>& v) {
  std::string s;
  for (size_t i = 0; i < v.size(); ++i) s += (i ? "," : "") + std::to_string(v[i]);
  return s;
}

const AttributeValue* Find(const ImageInfo& info, const std::string& name) {
  auto it = info.attributes.find(name);
  return it == info.attributes.end() ? nullptr : &it->second;
}

bool IntAttribute(const ImageInfo& info, const std::string& name, int* out) {
  const AttributeValue* v = Find(info, name);
  if (!v) return false;
  if (auto* i = std::get_if<int>(v)) return *out = *i, true;
  return false;
}

}  // namespace

Status WriteTextonAnalysis(const std::filesystem::path& path, const TextonAnalysis& a) {
  if (a.levels.empty()) return Status::Error(path.string() + ": a texton analysis without levels");
  std::vector<ExrPartHeader> parts;
  for (size_t l = 0; l < a.levels.size(); ++l) {
    const TextonLevel& level = a.levels[l];
    ExrPartHeader labels{"labels" + std::to_string(l), level.width, level.height, 1, {}};
    labels.options.format = PixelFormat::kFloat;
    labels.options.channel_names = {"texton"};
    labels.options.attributes["mesocap:quantity"] = std::string(kQuantity);
    labels.options.attributes["mesocap:level"] = int(l);
    labels.options.attributes["mesocap:layout"] = std::string(kLayout);
    labels.options.attributes["mesocap:spacing"] = level.spacing;
    labels.options.attributes["mesocap:levels"] = int(a.levels.size());
    labels.options.attributes["mesocap:textons"] = level.textons;
    labels.options.attributes["mesocap:energy_kept"] = float(level.energy_kept);
    labels.options.attributes["mesocap:slice_count"] = a.slice_count;
    labels.options.attributes["mesocap:representative_slices"] = JoinInts(a.representative_slices);
    ExrPartHeader gamma{"gamma" + std::to_string(l), level.textons + 1, level.textons + 1, 1, {}};
    gamma.options.format = PixelFormat::kFloat;
    gamma.options.channel_names = {"gamma"};
    parts.push_back(std::move(labels));
    parts.push_back(std::move(gamma));
  }
  return WriteMultiPartExr(path, parts, [&](int k) -> StatusOr<Image> {
    const TextonLevel& level = a.levels[k / 2];
    if (k % 2 == 0) {
      Image labels(level.width, level.height, 1);
      for (size_t t = 0; t < level.labels.size(); ++t) labels.data()[t] = float(level.labels[t]);
      return labels;
    }
    const int n = level.textons + 1;
    Image gamma(n, n, 1);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) gamma.at(j, i) = float(level.gamma(i, j));
    return gamma;
  });
}

StatusOr<TextonAnalysis> ReadTextonAnalysis(const std::filesystem::path& path) {
  auto fail = [&](const std::string& why) { return Status::Error(path.string() + ": " + why); };
  auto info = ReadImageInfo(path, 0);
  if (!info.ok()) return info.status();
  int levels = 0;
  if (!IntAttribute(*info, "mesocap:levels", &levels)) return fail("not a texton analysis (no mesocap:levels)");
  if (levels < 1 || levels > kMaxTextonLevels) return fail("declares " + std::to_string(levels) + " levels (1..8)");
  const AttributeValue* layout = Find(*info, "mesocap:layout");
  const std::string* layout_name = layout ? std::get_if<std::string>(layout) : nullptr;
  if (!layout_name || *layout_name != kLayout)
    return fail("a texton pyramid from an older mesocap, not a Gaussian stack: rerun synth without --analysis to make a new one");
  TextonAnalysis a;
  IntAttribute(*info, "mesocap:slice_count", &a.slice_count);
  ImageReadOptions read;
  read.linearize = false;
  read.max_channels = 1;
  for (int l = 0; l < levels; ++l) {
    auto part_info = ReadImageInfo(path, 2 * l);
    if (!part_info.ok()) return part_info.status();
    TextonLevel level;
    if (!IntAttribute(*part_info, "mesocap:textons", &level.textons) || level.textons < 1 || level.textons > 65535)
      return fail("level " + std::to_string(l) + " declares no valid texton count");
    read.part = 2 * l;
    auto labels = ReadImage(path, read);
    if (!labels.ok()) return labels.status();
    read.part = 2 * l + 1;
    auto gamma = ReadImage(path, read);
    if (!gamma.ok()) return gamma.status();
    const int n = level.textons + 1;
    if (gamma->width() != n || gamma->height() != n)
      return fail("level " + std::to_string(l) + "'s Gamma is not " + std::to_string(n) + "x" + std::to_string(n));
    level.width = labels->width(), level.height = labels->height();
    level.labels.resize(labels->pixel_count());
    for (size_t t = 0; t < labels->pixel_count(); ++t) {
      const float v = labels->data()[t];
      if (!(v >= 0 && v < float(level.textons) && v == std::floor(v)))
        return fail("level " + std::to_string(l) + " has a label that is not a texton index");
      level.labels[t] = int32_t(v);
    }
    level.gamma.resize(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const float g = gamma->at(j, i);
        if (!std::isfinite(g) || g != gamma->at(i, j)) return fail("level " + std::to_string(l) + "'s Gamma is not symmetric and finite");
        level.gamma(i, j) = g;
      }
    if (l > 0 && (level.width != a.levels[0].width || level.height != a.levels[0].height))
      return fail("level " + std::to_string(l) + " is not the size of level 0");
    level.spacing = 1 << l;
    a.levels.push_back(std::move(level));
  }
  if (const AttributeValue* v = Find(*info, "mesocap:representative_slices"))
    if (auto* s = std::get_if<std::string>(v)) {
      size_t at = 0;
      while (at < s->size()) {
        const size_t comma = std::min(s->find(',', at), s->size());
        a.representative_slices.push_back(std::atoi(s->substr(at, comma - at).c_str()));
        at = comma + 1;
      }
    }
  return a;
}

}  // namespace mesocap

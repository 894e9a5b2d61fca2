#include "synth/texton_analysis.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <string>

#include <opencv2/imgproc.hpp>

#include "core/image_io.h"
#include "core/parallel.h"
#include "synth/exemplar.h"
#include "synth/filter_bank.h"
#include "synth/kmeans.h"

namespace mesocap {
namespace {

constexpr int kMinLevelSide = 8;  // a coarser level would hold too few texels to cluster

// Gaussian pyramid level `level` of a one-channel image (OpenCV's 5-tap pyrDown per level).
Image Reduced(Image image, int level) {
  for (int l = 0; l < level; ++l) {
    cv::Mat down;
    cv::pyrDown(image.AsMat(), down, cv::Size((image.width() + 1) / 2, (image.height() + 1) / 2), cv::BORDER_REFLECT101);
    image = Image::FromMat(down);
  }
  return image;
}

// The levels whose shorter side stays at least kMinLevelSide (the finest always counts).
int UsableLevels(int width, int height, int wanted) {
  int levels = 1;
  while (levels < wanted) {
    width = (width + 1) / 2, height = (height + 1) / 2;
    if (std::min(width, height) < kMinLevelSide) break;
    ++levels;
  }
  return levels;
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
  if (!ReportProgress(progress, 1, 1, "representative slices")) return Status::Error("cancelled");
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
  if (levels < 1 || levels > 8) return Status::Error("the pyramid levels must be 1..8");
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
  auto slice_at = [&](int k, int level) -> StatusOr<Image> {
    auto s = read_luminance(k);
    if (!s.ok()) return s.status();
    if (s->width() != width || s->height() != height || s->channels() != 1)
      return Status::Error("slice " + std::to_string(k) + " is " + std::to_string(s->width()) + "x" +
                           std::to_string(s->height()) + ", slice 0 is " + std::to_string(width) + "x" + std::to_string(height));
    // Each slice divided by its RMS value: every light and view weighs the same in the clustering.
    // (The filters' responses are not equalised: giving the edge filters the Gaussians' weight
    // made the syntheses' subband statistics 1.8-2.4x worse on the virtual-rig weave and stones.)
    return Reduced(DividedByRms(std::move(*s)), level);
  };

  TextonAnalysis analysis;
  analysis.slice_count = slice_count;
  const int levels = UsableLevels(width, height, o.levels);
  const FilterBank finest(width, height);
  auto chosen = RepresentativeSlices(slice_count, [&](int k) { return slice_at(k, 0); }, finest, o, progress);
  if (!chosen.ok()) return chosen.status();
  analysis.representative_slices = *chosen;
  const int ns = int(chosen->size());

  int level_width = width, level_height = height;
  for (int l = 0; l < levels; ++l) {
    const std::string what = "textons, level " + std::to_string(l);
    std::unique_ptr<FilterBank> coarse;
    if (l > 0) coarse = std::make_unique<FilterBank>(level_width, level_height);
    const FilterBank& bank = l > 0 ? *coarse : finest;
    auto vectors = GeometryMapsOfSlices(
        ns, [&](int i) -> StatusOr<Image> {
          auto s = slice_at((*chosen)[i], l);
          if (!s.ok()) return s.status();
          return bank.Responses(*s);
        },
        o.dimensions, 1, /*normalize=*/false, o.num_threads,
        [&](int done, int total, const std::string&) { return ReportProgress(progress, done, total, what); });
    if (!vectors.ok()) return vectors.status();
    const Eigen::MatrixXd points = TexelMatrix(vectors->features).cast<double>();
    const int wanted = std::max(1, o.textons >> (2 * l));  // a quarter per coarser level (Tong §5.1)
    const KMeansResult clusters = KMeans(points, {wanted, o.kmeans_iterations, o.seed + uint32_t(l), o.num_threads});
    TextonLevel level;
    level.width = level_width, level.height = level_height;
    level.textons = int(clusters.centres.rows());
    level.labels.assign(clusters.labels.begin(), clusters.labels.end());
    Eigen::MatrixXd with_default(level.textons + 1, points.cols());
    with_default.topRows(level.textons) = clusters.centres;
    with_default.row(level.textons) = clusters.centres.colwise().mean();
    level.gamma = with_default * with_default.transpose();
    // Exactly symmetric, and in float precision, as textons.exr stores it: a run reusing the saved
    // analysis finds the same map as the run that made it.
    level.gamma = (0.5 * (level.gamma + level.gamma.transpose())).cast<float>().cast<double>();
    level.energy_kept = vectors->energy_kept;
    analysis.levels.push_back(std::move(level));
    if (vocabulary) vocabulary->push_back({std::move(vectors->features), clusters.centres});
    if (!ReportProgress(progress, l + 1, levels, what)) return Status::Error("cancelled");
    level_width = (level_width + 1) / 2, level_height = (level_height + 1) / 2;
  }
  analysis.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return analysis;
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
  if (levels < 1 || levels > 8) return fail("declares " + std::to_string(levels) + " levels (1..8)");
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
    if (l > 0 && (level.width != (a.levels.back().width + 1) / 2 || level.height != (a.levels.back().height + 1) / 2))
      return fail("level " + std::to_string(l) + " is not half the size of the level above");
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

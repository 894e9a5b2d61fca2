#include "synth/exemplar.h"

#include <algorithm>
#include <optional>
#include <map>
#include <random>

#include <Eigen/Dense>

#include "core/cancel.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "core/json.h"
#include "core/session_layout.h"
#include "core/slice_index.h"
#include "core/parallel.h"
#include "formats/ptm_file.h"
#include "reconstruct/ptm_legendre.h"

namespace mesocap {
namespace fs = std::filesystem;

std::string ExemplarKindToString(ExemplarKind kind) {
  switch (kind) {
    case ExemplarKind::kImage: return "image";
    case ExemplarKind::kBtf: return "btf";
    case ExemplarKind::kPtm: return "ptm";
  }
  return "?";
}

StatusOr<Image> Exemplar::ReadSlice(int k) const {
  MESOCAP_CHECK(k >= 0 && k < int(slices.size()), "slice index out of range");
  ImageReadOptions options;
  options.max_channels = 3;
  auto slice = ReadImage(slices[k].file, options);
  if (!slice.ok()) return slice.status();
  if (slice->width() != width || slice->height() != height || slice->channels() != 3)
    return Status::Error(slices[k].file.string() + ": " + std::to_string(slice->width()) + "x" +
                         std::to_string(slice->height()) + "x" + std::to_string(slice->channels()) +
                         ", the exemplar's slices are " + std::to_string(width) + "x" + std::to_string(height) + " RGB");
  return slice;
}

namespace {

// Rows of the random test matrix for (slice k, channel c): regenerated on demand from the seed.
Eigen::MatrixXd TestRows(int k, int channels, int columns) {
  std::mt19937_64 rng(0x5eed0000ull + uint64_t(k));
  std::normal_distribution<double> normal;
  Eigen::MatrixXd rows(channels, columns);
  for (int c = 0; c < channels; ++c)
    for (int j = 0; j < columns; ++j) rows(c, j) = normal(rng);
  return rows;
}


Eigen::MatrixXd Orthonormalize(const Eigen::MatrixXd& y) {
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(y);
  return qr.householderQ() * Eigen::MatrixXd::Identity(y.rows(), y.cols());
}

constexpr double kKeptSliceBytes = 512.0 * (1 << 20);

// Calls visit(k, slice) for every slice in order; slices are decoded `threads` at a time in
// parallel, visited one by one (the sums stay independent of the thread count).
Status ForEachSlice(int count, const std::function<StatusOr<Image>(int)>& read_slice, int num_threads,
                    const std::function<void(int, const Image&)>& visit) {
  const int batch = std::max(1, EffectiveThreadCount(num_threads));
  for (int first = 0; first < count; first += batch) {
    if (CancelRequested()) return Status::Cancelled();  // Ctrl-C: a full BTF's passes take minutes
    const int n = std::min(batch, count - first);
    std::vector<StatusOr<Image>> read(n, Status::Error("not read"));
    ParallelFor(0, n, [&](int i) { read[i] = read_slice(first + i); }, num_threads);
    for (int i = 0; i < n; ++i) {
      if (!read[i].ok()) return read[i].status();
      visit(first + i, *read[i]);
    }
  }
  return Status::Ok();
}

}  // namespace

TexelMatrixMap TexelMatrix(const Image& image) {
  return {image.data(), Eigen::Index(image.pixel_count()), Eigen::Index(image.channels())};
}

Image DividedByRms(Image image) {
  double sum = 0;
  for (size_t i = 0; i < image.size(); ++i) sum += double(image.data()[i]) * image.data()[i];
  const double rms = std::sqrt(sum / std::max<size_t>(1, image.size()));
  if (rms > 0)
    for (size_t i = 0; i < image.size(); ++i) image.data()[i] = float(image.data()[i] / rms);
  return image;
}

StatusOr<SliceFeatures> GeometryMapsOfSlices(int count, const std::function<StatusOr<Image>(int)>& read_raw,
                                             int components, int power_iterations, bool normalize, int num_threads,
                                             const ProgressFn& progress) {
  MESOCAP_CHECK(count > 0 && components > 0, "no slices or no components");
  // Every slice weighs the same in the distances, whatever its exposure: a grazing-lit slice's
  // shadows matter as much as a head-on slice's colours.
  const std::function<StatusOr<Image>(int)> read_normalized = [&](int k) -> StatusOr<Image> {
    auto s = read_raw(k);
    if (!s.ok() || !normalize) return s;
    return DividedByRms(std::move(*s));
  };
  auto first = read_normalized(0);
  if (!first.ok()) return first.status();
  // Every pass below reads every slice (decoding, filtering): the slices are kept from the first
  // pass when all of them fit in kKeptSliceBytes (the demo's BTF: 57 MB, its textons' responses:
  // 75 MB), else read again.
  const bool keep = double(count) * double(first->size()) * sizeof(float) <= kKeptSliceBytes;
  std::vector<std::optional<Image>> kept_slices(keep ? size_t(count) : 0);
  if (keep) kept_slices[0] = *first;
  const std::function<StatusOr<Image>(int)> read_slice = [&](int k) -> StatusOr<Image> {
    if (keep && kept_slices[size_t(k)]) return *kept_slices[size_t(k)];
    auto s = read_normalized(k);
    if (keep && s.ok()) kept_slices[size_t(k)] = *s;
    return s;
  };
  const int width = first->width(), height = first->height(), channels = first->channels();
  const Eigen::Index texels = Eigen::Index(first->pixel_count());
  const int columns = count * channels;
  const int passes = 2 + power_iterations;
  int pass = 0;
  auto report = [&](int k) { return ReportProgress(progress, pass * count + k + 1, passes * count, "SVD of the slices"); };

  SliceFeatures result;
  if (columns <= components) {  // few enough values per texel: keep them all, exactly
    result.features = Image(width, height, columns);
    MESOCAP_RETURN_IF_ERROR(ForEachSlice(count, read_slice, num_threads, [&](int k, const Image& s) {
      for (size_t t = 0; t < s.pixel_count(); ++t)
        for (int c = 0; c < channels; ++c) result.features.data()[t * columns + k * channels + c] = s.data()[t * channels + c];
    }));
    return result;
  }

  const int sketch = std::min(columns, components + 10);  // Halko et al.'s oversampling p = 10
  double frobenius = 0;
  Eigen::MatrixXd y = Eigen::MatrixXd::Zero(texels, sketch);
  MESOCAP_RETURN_IF_ERROR(ForEachSlice(count, read_slice, num_threads, [&](int k, const Image& s) {
    const Eigen::MatrixXd a = TexelMatrix(s).cast<double>();
    y.noalias() += a * TestRows(k, channels, sketch);
    frobenius += a.squaredNorm();
    report(k);
  }));
  Eigen::MatrixXd q = Orthonormalize(y);
  for (int it = 0; it < power_iterations; ++it) {  // y = A A^T q, one slice at a time
    ++pass;
    y.setZero();
    MESOCAP_RETURN_IF_ERROR(ForEachSlice(count, read_slice, num_threads, [&](int k, const Image& s) {
      const Eigen::MatrixXd a = TexelMatrix(s).cast<double>();
      y.noalias() += a * (a.transpose() * q);
      report(k);
    }));
    q = Orthonormalize(y);
  }
  // B = Q^T A is sketch x columns; B B^T gives its left singular vectors and values.
  ++pass;
  Eigen::MatrixXd bbt = Eigen::MatrixXd::Zero(sketch, sketch);
  MESOCAP_RETURN_IF_ERROR(ForEachSlice(count, read_slice, num_threads, [&](int k, const Image& s) {
    const Eigen::MatrixXd b = q.transpose() * TexelMatrix(s).cast<double>();
    bbt.noalias() += b * b.transpose();
    report(k);
  }));
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(bbt);  // ascending eigenvalues
  const int kept = std::min(components, sketch);
  Eigen::MatrixXd u(sketch, kept);
  double energy = 0;
  for (int j = 0; j < kept; ++j) {
    const int src = sketch - 1 - j;
    const double sigma = std::sqrt(std::max(0.0, eig.eigenvalues()(src)));
    u.col(j) = eig.eigenvectors().col(src) * sigma;
    energy += sigma * sigma;
  }
  const Eigen::MatrixXd g = q * u;  // texels x kept: U Sigma of the SVD
  result.features = Image(width, height, kept);
  for (Eigen::Index t = 0; t < texels; ++t)
    for (int j = 0; j < kept; ++j) result.features.data()[t * kept + j] = float(g(t, j));
  result.energy_kept = frobenius > 0 ? energy / frobenius : 1.0;
  return result;
}

Exemplar ImageExemplar(Image image) {
  Exemplar e;
  e.kind = ExemplarKind::kImage;
  e.width = image.width();
  e.height = image.height();
  if (image.channels() >= 3) {
    e.preview = Image(image.width(), image.height(), 3);
    for (size_t t = 0; t < image.pixel_count(); ++t)
      std::copy_n(image.data() + t * image.channels(), 3, e.preview.data() + 3 * t);
  } else {
    e.preview = Image(image.width(), image.height(), 3);
    for (size_t t = 0; t < image.pixel_count(); ++t)
      std::fill_n(e.preview.data() + 3 * t, 3, image.data()[t * image.channels()]);
  }
  e.features = image;
  e.image = std::move(image);
  return e;
}

StatusOr<Exemplar> BtfExemplar(std::vector<ExemplarSlice> slices, const ExemplarOptions& options, const ProgressFn& progress) {
  if (slices.empty()) return Status::Error("a BTF exemplar needs at least one slice");
  Exemplar e;
  e.kind = ExemplarKind::kBtf;
  e.slices = std::move(slices);
  auto info = ReadImageInfo(e.slices[0].file);
  if (!info.ok()) return info.status();
  e.width = info->width;
  e.height = info->height;
  // The preview: the most head-on view, lit most head-on.
  int best = 0;
  for (int k = 1; k < int(e.slices.size()); ++k) {
    const auto& s = e.slices[k];
    const auto& b = e.slices[best];
    if (std::tie(s.theta_o_deg, s.theta_i_deg) < std::tie(b.theta_o_deg, b.theta_i_deg)) best = k;
  }
  auto preview = e.ReadSlice(best);
  if (!preview.ok()) return preview.status();
  e.preview = std::move(*preview);
  if (!options.features) return e;
  auto features = GeometryMapsOfSlices(int(e.slices.size()), [&](int k) { return e.ReadSlice(k); },
                                       options.svd_components, options.svd_power_iterations, options.normalize_slices,
                                       options.num_threads, progress);
  if (!features.ok()) return features.status();
  e.features = std::move(features->features);
  e.svd_energy_kept = features->energy_kept;
  return e;
}

namespace {

StatusOr<std::vector<ExemplarSlice>> SlicesFromIndex(const fs::path& index_path, int board) {
  auto index = ReadSliceIndex(index_path);
  if (!index.ok()) return index.status();
  std::map<int, std::vector<ExemplarSlice>> by_board;
  for (const SliceIndexEntry& e : index->slices)
    by_board[e.board].push_back({e.file, e.light, e.view, e.theta_i_deg, e.phi_i_deg, e.theta_o_deg, e.phi_o_deg});
  if (by_board.empty()) return Status::Error(index_path.string() + ": lists no slices");
  if (board >= 0) {
    auto it = by_board.find(board);
    if (it == by_board.end()) return Status::Error(index_path.string() + ": no slices of board " + std::to_string(board));
    return it->second;
  }
  // The most head-on board: smallest mean view incidence.
  auto mean_theta = [](const std::vector<ExemplarSlice>& v) {
    double t = 0;
    for (const auto& s : v) t += s.theta_o_deg;
    return t / v.size();
  };
  auto best = by_board.begin();
  for (auto it = by_board.begin(); it != by_board.end(); ++it)
    if (mean_theta(it->second) < mean_theta(best->second)) best = it;
  return best->second;
}

}  // namespace

StatusOr<Exemplar> LoadExemplar(const fs::path& path, const ExemplarOptions& options, const ProgressFn& progress) {
  if (!options.Check()) return Status::Error("invalid exemplar options");
  std::error_code ec;
  if (!fs::exists(path, ec)) return Status::Error(path.string() + ": no such file or folder");
  fs::path index;
  if (fs::is_directory(path, ec)) {
    for (const fs::path& candidate : {BtfFolder{path}.index(), SessionLayout(path).slices().index()})
      if (fs::is_regular_file(candidate, ec)) {
        index = candidate;
        break;
      }
    if (index.empty())
      return Status::Error(path.string() + ": a folder without " + BtfFolder{path}.index().filename().string() + " or " +
                           SessionLayout("").slices().index().string() + " is not a BTF");
  } else if (path.extension() == ".json") {
    index = path;
  }
  if (!index.empty()) {
    auto slices = SlicesFromIndex(index, options.board);
    if (!slices.ok()) return slices.status();
    auto e = BtfExemplar(std::move(*slices), options, progress);
    if (e.ok()) e->path = path;
    return e;
  }
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  if (ext == ".ptm") {
    auto ptm = ReadPtmFile(path);
    if (!ptm.ok()) return ptm.status();
    Exemplar e;
    e.kind = ExemplarKind::kPtm;
    e.path = path;
    e.width = ptm->width();
    e.height = ptm->height();
    // Each colour channel's reflectance function in the orthonormal Legendre basis: feature
    // distances are L2 distances between the functions (reconstruct/ptm_legendre.h).
    e.features = PtmLegendreCoefficients(*ptm);
    e.preview = RelightPtm(*ptm, Eigen::Vector3d::UnitZ());
    e.ptm = std::move(*ptm);
    return e;
  }
  auto image = ReadImage(path);
  if (!image.ok()) return image.status();
  Exemplar e = ImageExemplar(std::move(*image));
  e.path = path;
  return e;
}

namespace {

Eigen::Vector3d PtmAppearanceLight(int k) {
  if (k == 0) return Eigen::Vector3d::UnitZ();
  return DirectionFromAnglesDeg(k <= 8 ? 30 : 60, 45.0 * ((k - 1) % 8) + (k <= 8 ? 0 : 22.5));
}

}  // namespace

int AppearanceImageCount(const Exemplar& e) {
  switch (e.kind) {
    case ExemplarKind::kBtf: return int(e.slices.size());
    case ExemplarKind::kPtm: return 17;
    case ExemplarKind::kImage: return 1;
  }
  return 1;
}

StatusOr<Image> AppearanceLuminance(const Exemplar& e, int k) {
  switch (e.kind) {
    case ExemplarKind::kBtf: {
      auto slice = e.ReadSlice(k);
      if (!slice.ok()) return slice.status();
      return Luminance(*slice);
    }
    case ExemplarKind::kPtm: return Luminance(RelightPtm(e.ptm, PtmAppearanceLight(k), true, 1));
    case ExemplarKind::kImage: return Luminance(e.image);
  }
  return Status::Error("unknown exemplar kind");
}

}  // namespace mesocap

#include "reconstruct/slice_set.h"

#include <atomic>
#include <chrono>
#include <map>

#include <opencv2/imgproc.hpp>

#include "core/cancel.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "core/json.h"
#include "core/parallel.h"
#include "core/slice_index.h"
#include "core/text_format.h"

namespace mesocap {
namespace {

struct IndexedSlice {
  std::filesystem::path file;
  int board = 0;
  Eigen::Vector3d light, view;
  double texel_px = 0;  // in the photo (SliceIndexEntry::texel_px)
};

Image ResampleSquare(const Image& image, int size) {
  if (size <= 0 || (image.width() == size && image.height() == size)) return image;
  cv::Mat out;
  cv::resize(image.AsMat(), out, cv::Size(size, size), 0, 0, size < image.width() ? cv::INTER_AREA : cv::INTER_LINEAR);
  return Image::FromMat(out);
}

bool IsPowerOfTwo(int n) { return n > 0 && (n & (n - 1)) == 0; }

// For each slice, the slice of the same view whose light is nearest its own, if within
// `max_deg` (else -1: further apart their signals differ, and the difference is not noise).
std::vector<int> NearestLightOfSameView(const std::vector<const IndexedSlice*>& slices, const std::vector<int>& view_of,
                                        double max_deg) {
  std::vector<int> partner(slices.size(), -1);
  for (size_t k = 0; k < slices.size(); ++k) {
    double nearest = max_deg;
    for (size_t j = 0; j < slices.size(); ++j)
      if (j != k && view_of[j] == view_of[k]) {
        const double angle = AngleBetweenDeg(slices[k]->light, slices[j]->light);
        if (angle < nearest) nearest = angle, partner[k] = int(j);
      }
  }
  return partner;
}

// The index's slices by board, each board's near-duplicate lights dropped (Delaunay needs distinct
// points), listed in the report.
std::map<int, std::vector<IndexedSlice>> SlicesByBoard(const SliceIndex& index, double duplicate_light_deg,
                                                       SliceSetReport* report) {
  std::map<int, std::vector<IndexedSlice>> boards;
  for (const SliceIndexEntry& entry : index.slices) {
    IndexedSlice s{entry.file, entry.board, entry.light, entry.view, entry.texel_px};
    auto& kept = boards[s.board];
    bool duplicate = false;
    for (const auto& other : kept) duplicate |= AngleBetweenDeg(other.light, s.light) < duplicate_light_deg;
    if (duplicate) {
      report->skipped.push_back(s.file.filename().string() + ": light within " + std::to_string(duplicate_light_deg) +
                                " deg of another slice of board " + std::to_string(s.board));
      continue;
    }
    kept.push_back(s);
  }
  return boards;
}

// The boards, each with its view (the mean of its slices' view directions), and which of them is
// the top view: the most head-on with slices enough to interpolate its lights (-1: none).
struct BoardViews {
  std::vector<int> ids;
  std::vector<Eigen::Vector3d> views;
  int top = -1;
};
BoardViews ViewsOf(const std::map<int, std::vector<IndexedSlice>>& boards) {
  BoardViews out;
  for (const auto& [id, slices] : boards) {
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    for (const auto& s : slices) v += s.view;
    out.ids.push_back(id);
    out.views.push_back(v.normalized());
  }
  for (size_t b = 0; b < out.views.size(); ++b)
    if (int(boards.at(out.ids[b]).size()) >= kMinSlicesPerView &&
        (out.top < 0 || out.views[b].z() > out.views[size_t(out.top)].z()))
      out.top = int(b);
  return out;
}

// Every slice's statistics and mean colour (or the error that kept it out), and the top view's
// slices themselves (the base textures).
struct SliceReadings {
  std::vector<SliceStatistics> stats;
  std::vector<Eigen::Vector3d> mean_rgb;
  std::vector<Image> top_images;
  std::vector<std::string> errors;
};

// Reads and resamples slices; each one's capture blur in its texels once resampled to
// options.size (0: none known).
class SliceReader {
 public:
  SliceReader(const std::vector<const IndexedSlice*>& slices, const SliceSetOptions& options)
      : slices_(slices), options_(options) {}
  Image Read(int k, std::string* error, double* blur_texels) const {
    auto image = ReadImage(slices_[size_t(k)]->file);
    if (!image.ok()) {
      *error = image.status().message();
      return {};
    }
    Image slice = ResampleSquare(*image, options_.size);
    const double texel_px = slices_[size_t(k)]->texel_px * image->width() / std::max(slice.width(), 1);
    *blur_texels = options_.capture_blur_px > 0 && texel_px > 0 ? options_.capture_blur_px / texel_px : 0.0;
    if (!IsPowerOfTwo(slice.width()) || slice.width() != slice.height()) {
      *error = "slice is " + std::to_string(slice.width()) + "x" + std::to_string(slice.height()) +
               ", not a power-of-two square (use --size)";
      return {};
    }
    return slice;
  }

 private:
  const std::vector<const IndexedSlice*>& slices_;
  const SliceSetOptions& options_;
};

// The statistics of every slice of `all` (the first `top_count` are the top view's, already read
// into readings->top_images with their blur), streamed on all cores. False if cancelled.
bool ComputeStatistics(const std::vector<const IndexedSlice*>& all, const std::vector<int>& view_of, int top_count,
                       const std::vector<double>& top_blur, const SliceSetOptions& options,
                       const StatisticalBtfOptions& btf_options, const ProgressFn& progress, SliceReadings* readings) {
  const SliceReader reader(all, options);
  const bool chromaticity = btf_options.colour.space() == ColourSpace::kChromaticity;
  // The chromaticities' blur undone (channels 1 and 2); the brightness keeps its own, as sharpening
  // it raises its noise as much as its detail.
  const auto sharpened = [&](const Image& slice, double blur_texels) {
    Image channels = btf_options.colour.Forward(slice);
    if (chromaticity) UndoGaussianBlur(&channels, blur_texels, /*first_channel=*/1);
    return channels;
  };
  const std::vector<int> partner = options.remove_chroma_noise && chromaticity
                                       ? NearestLightOfSameView(all, view_of, kNearHullDeg)
                                       : std::vector<int>(all.size(), -1);
  readings->stats.resize(all.size());
  readings->mean_rgb.assign(all.size(), Eigen::Vector3d::Zero());
  std::atomic<int> done = 0;
  std::atomic<bool> cancelled = false;
  ParallelFor(0, int(all.size()), [&](int k) {
    if (cancelled) return;
    double blur = k < top_count ? top_blur[size_t(k)] : 0.0;
    const Image slice = k < top_count ? Image() : reader.Read(k, &readings->errors[size_t(k)], &blur);
    const Image& measured = k < top_count ? readings->top_images[size_t(k)] : slice;
    if (readings->errors[size_t(k)].empty()) {
      const Image channels = sharpened(measured, blur);
      SliceStatistics& stats = readings->stats[size_t(k)];
      stats = ComputeSliceStatistics(channels, btf_options.statistics);
      // Each slice's noise out of its chromaticities' statistics, measured against its partner.
      if (const int j = partner[size_t(k)]; j >= 0) {
        std::string ignored;  // the partner's own pass reports its errors
        double partner_blur = j < top_count ? top_blur[size_t(j)] : 0.0;
        const Image loaded = j < top_count ? Image() : reader.Read(j, &ignored, &partner_blur);
        const Image& other = j < top_count ? readings->top_images[size_t(j)] : loaded;  // top slices: no copy
        if (other.width() == measured.width() && other.height() == measured.height() &&
            other.channels() == measured.channels()) {
          const Image noise = NoiseDifference(channels, sharpened(other, partner_blur));
          RemoveNoiseVariance(&stats, ComputeSliceStatistics(noise, btf_options.statistics), /*first_channel=*/1);
        }
      }
      if (measured.channels() == 3) readings->mean_rgb[size_t(k)] = MeanRgb(measured);  // else unused (no colour)
    }
    if (!ReportProgress(progress, ++done, int(all.size()), "slice statistics")) cancelled = true;
  }, options.btf.num_threads);
  return !cancelled;
}

}  // namespace

bool SliceSetOptions::Check() const {
  return btf.Check() && (size == 0 || IsPowerOfTwo(size)) && duplicate_light_deg >= 0 && capture_blur_px >= 0 &&
         capture_blur_px <= 10;
}

namespace {

// `top_only`: the top board's slices alone.
StatusOr<StatisticalBtfInputs> LoadMeasuredSlices(const std::filesystem::path& index_json, const SliceSetOptions& options,
                                            bool top_only, SliceSetReport& rep, const ProgressFn& progress) {
  if (!options.Check()) return Status::Error("invalid slice-set options (size must be a power of two)");
  auto index = ReadSliceIndex(index_json);
  if (!index.ok()) return index.status();

  std::map<int, std::vector<IndexedSlice>> boards = SlicesByBoard(*index, options.duplicate_light_deg, &rep);
  if (boards.empty()) return Status::Error(index_json.string() + ": no slices");
  const BoardViews boards_seen = ViewsOf(boards);
  const int top = boards_seen.top;
  if (top < 0) return Status::Error(index_json.string() + ": no board has 3 or more slices (distinct lights)");
  rep.top_board = boards_seen.ids[size_t(top)];
  if (const double tilt = AngleBetweenDeg(boards_seen.views[size_t(top)], Eigen::Vector3d::UnitZ());
      tilt > options.max_top_view_deg)
    rep.warnings.push_back(Format("no top view: the most head-on board with 3 or more slices, board %d, is seen %.0f deg "
                                  "from its normal (more than %.0f); the reconstruction's base textures come from that "
                                  "tilted view",
                                  rep.top_board, tilt, options.max_top_view_deg));

  // The top board's slices first: they are kept as base textures and give the colour basis the
  // statistics are taken in. Then every other slice's statistics, streamed.
  std::vector<const IndexedSlice*> all;
  std::vector<int> view_of;
  for (const auto& s : boards[rep.top_board]) all.push_back(&s), view_of.push_back(top);
  const int top_count = int(all.size());
  for (size_t b = 0; b < boards_seen.ids.size() && !top_only; ++b)
    if (int(b) != top)
      for (const auto& s : boards[boards_seen.ids[b]]) all.push_back(&s), view_of.push_back(int(b));
  SliceReadings readings;
  readings.errors.resize(all.size());
  readings.top_images.resize(size_t(top_count));
  std::vector<double> top_blur(size_t(top_count), 0.0);
  const SliceReader reader(all, options);
  ParallelFor(
      0, top_count,
      [&](int k) {
        if (CancelRequested()) return;
        readings.top_images[size_t(k)] = reader.Read(k, &readings.errors[size_t(k)], &top_blur[size_t(k)]);
      },
      options.btf.num_threads);
  if (CancelRequested()) return Status::Cancelled();
  // (An unreadable slice is an empty image, which the basis skips.)
  StatisticalBtfOptions btf_options = WithColourChannels(options.btf, readings.top_images);
  btf_options.chromaticity_from_top_view = options.chroma_from_top.value_or(index->chroma_subsampled_shots);
  rep.chroma_from_top = btf_options.chromaticity_from_top_view;
  if (!ComputeStatistics(all, view_of, top_count, top_blur, options, btf_options, progress, &readings))
    return Status::Cancelled();

  std::vector<MeasuredView> measured(boards_seen.ids.size());
  StatisticalBtfInputs out;
  out.btf_options = btf_options;
  for (size_t k = 0; k < all.size(); ++k) {
    if (!readings.errors[k].empty()) {
      rep.skipped.push_back(all[k]->file.filename().string() + ": " + readings.errors[k]);
      continue;
    }
    MeasuredView& v = measured[size_t(view_of[k])];
    v.view = boards_seen.views[size_t(view_of[k])];
    v.lights.push_back(all[k]->light);
    v.statistics.push_back(std::move(readings.stats[k]));
    v.mean_rgb.push_back(readings.mean_rgb[k]);
    if (view_of[k] == top)
      out.top_slices.push_back(std::move(readings.top_images[k])), out.top_lights.push_back(all[k]->light);
    ++rep.slices_used;
  }
  for (size_t b = 0; b < measured.size(); ++b) {
    if (top_only && int(b) != top) continue;
    if (int(measured[b].lights.size()) < kMinSlicesPerView) {
      rep.skipped.push_back("board " + std::to_string(boards_seen.ids[b]) + ": fewer than 3 usable slices, view not used");
      continue;
    }
    out.views.push_back(std::move(measured[b]));
  }
  rep.views = int(out.views.size());
  rep.top_lights = int(out.top_lights.size());
  return out;
}

}  // namespace

StatusOr<StatisticalBtfInputs> LoadStatisticalBtfInputs(const std::filesystem::path& index_json,
                                                        const SliceSetOptions& options, SliceSetReport* report,
                                                        const ProgressFn& progress) {
  SliceSetReport local;
  return LoadMeasuredSlices(index_json, options, /*top_only=*/false, report ? *report : local, progress);
}

StatusOr<StatisticalBtf> CreateStatisticalBtf(StatisticalBtfInputs inputs) {
  return StatisticalBtf::Create(std::move(inputs.top_slices), std::move(inputs.top_lights), std::move(inputs.views),
                                inputs.btf_options);
}

StatusOr<StatisticalBtf> LoadStatisticalBtf(const std::filesystem::path& index_json, const SliceSetOptions& options,
                                            SliceSetReport* report, const ProgressFn& progress) {
  const auto start = std::chrono::steady_clock::now();
  SliceSetReport local;
  SliceSetReport& rep = report ? *report : local;
  auto loaded = LoadStatisticalBtfInputs(index_json, options, &rep, progress);
  if (!loaded.ok()) return loaded.status();
  auto btf = CreateStatisticalBtf(std::move(*loaded));
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!btf.ok()) return Status::Error(index_json.string() + ": " + btf.status().message());
  return btf;
}

StatusOr<MeasuredView> LoadTopView(const std::filesystem::path& index_json, const SliceSetOptions& options,
                                   SliceSetReport* report) {
  SliceSetReport local;
  SliceSetReport& rep = report ? *report : local;
  auto loaded = LoadMeasuredSlices(index_json, options, /*top_only=*/true, rep, nullptr);
  if (!loaded.ok()) return loaded.status();
  if (loaded->views.empty())
    return Status::Error(index_json.string() + ": the top board has fewer than 3 usable slices");
  return std::move(loaded->views.front());
}

}  // namespace mesocap

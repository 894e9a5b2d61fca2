#include "reconstruct/slice_set.h"

#include <atomic>
#include <chrono>
#include <map>
#include <mutex>

#include <opencv2/imgproc.hpp>

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

}  // namespace

bool SliceSetOptions::Check() const {
  return btf.Check() && (size == 0 || IsPowerOfTwo(size)) && duplicate_light_deg >= 0 && capture_blur_px >= 0 &&
         capture_blur_px <= 10;
}

StatusOr<StatisticalBtf> LoadStatisticalBtf(const std::filesystem::path& index_json, const SliceSetOptions& options,
                                            SliceSetReport* report, const ProgressFn& progress) {
  const auto start = std::chrono::steady_clock::now();
  if (!options.Check()) return Status::Error("invalid slice-set options (size must be a power of two)");
  auto index = ReadSliceIndex(index_json);
  if (!index.ok()) return index.status();
  SliceSetReport local;
  SliceSetReport& rep = report ? *report : local;

  // Group by board; drop near-duplicate lights within a board.
  std::map<int, std::vector<IndexedSlice>> boards;
  for (const SliceIndexEntry& entry : index->slices) {
    IndexedSlice s{entry.file, entry.board, entry.light, entry.view, entry.texel_px};
    auto& kept = boards[s.board];
    bool duplicate = false;
    for (const auto& other : kept) duplicate |= AngleBetweenDeg(other.light, s.light) < options.duplicate_light_deg;
    if (duplicate) {
      rep.skipped.push_back(s.file.filename().string() + ": light within " + std::to_string(options.duplicate_light_deg) +
                            " deg of another slice of board " + std::to_string(s.board));
      continue;
    }
    kept.push_back(s);
  }
  if (boards.empty()) return Status::Error(index_json.string() + ": no slices");

  // Each board's view: the mean of its slices' view directions; the top board sees most head-on.
  std::vector<int> board_ids;
  std::vector<Eigen::Vector3d> views;
  for (const auto& [id, slices] : boards) {
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    for (const auto& s : slices) v += s.view;
    board_ids.push_back(id);
    views.push_back(v.normalized());
  }
  // The top view: the most head-on board with slices enough to interpolate its lights.
  int top = -1;
  for (size_t b = 0; b < views.size(); ++b)
    if (int(boards[board_ids[b]].size()) >= kMinSlicesPerView && (top < 0 || views[b].z() > views[top].z())) top = int(b);
  if (top < 0) return Status::Error(index_json.string() + ": no board has 3 or more slices (distinct lights)");
  rep.top_board = board_ids[top];
  if (const double tilt = AngleBetweenDeg(views[top], Eigen::Vector3d::UnitZ()); tilt > options.max_top_view_deg)
    rep.warnings.push_back(Format("no top view: the most head-on board with 3 or more slices, board %d, is seen %.0f deg "
                                  "from its normal (more than %.0f); the reconstruction's base textures come from that "
                                  "tilted view",
                                  board_ids[top], tilt, options.max_top_view_deg));

  // The top board's slices first: they are kept as base textures and give the colour basis the
  // statistics are taken in. Then every other slice's statistics, streamed.
  std::vector<const IndexedSlice*> all;
  std::vector<int> view_of;
  for (const auto& s : boards[board_ids[top]]) all.push_back(&s), view_of.push_back(top);
  const int top_count = int(all.size());
  for (size_t b = 0; b < board_ids.size(); ++b)
    if (int(b) != top)
      for (const auto& s : boards[board_ids[b]]) all.push_back(&s), view_of.push_back(int(b));
  std::vector<SliceStatistics> stats(all.size());
  std::vector<Eigen::Vector3d> mean_rgb(all.size(), Eigen::Vector3d::Zero());
  std::vector<Image> images(all.size());
  std::vector<std::string> errors(all.size());
  std::atomic<int> done = 0;
  std::atomic<bool> cancelled = false;
  // Each slice's capture blur in its texels once resampled to options.size (0: none known).
  const bool undo_blur = options.capture_blur_px > 0;
  auto load = [&](int k, std::string* error, double* blur_texels) -> Image {
    auto image = ReadImage(all[k]->file);
    if (!image.ok()) {
      *error = image.status().message();
      return {};
    }
    Image slice = ResampleSquare(*image, options.size);
    const double texel_px = all[k]->texel_px * image->width() / std::max(slice.width(), 1);
    *blur_texels = undo_blur && texel_px > 0 ? options.capture_blur_px / texel_px : 0.0;
    if (!IsPowerOfTwo(slice.width()) || slice.width() != slice.height()) {
      *error = "slice is " + std::to_string(slice.width()) + "x" + std::to_string(slice.height()) +
               ", not a power-of-two square (use --size)";
      return {};
    }
    return slice;
  };
  std::vector<double> blur(all.size(), 0.0);
  auto read = [&](int k) { return load(k, &errors[k], &blur[k]); };
  ParallelFor(0, top_count, [&](int k) { images[k] = read(k); }, options.btf.num_threads);
  // (An unreadable slice is an empty image, which the basis skips.)
  StatisticalBtfOptions btf_options = WithColourChannels(options.btf, std::span(images.data(), top_count));
  btf_options.chromaticity_from_top_view = options.chroma_from_top.value_or(index->chroma_subsampled_shots);
  rep.chroma_from_top = btf_options.chromaticity_from_top_view;
  const bool chromaticity = btf_options.colour.space() == ColourSpace::kChromaticity;
  const bool remove_noise = options.remove_chroma_noise && chromaticity;
  // The chromaticities' blur undone (channels 1 and 2); the brightness keeps its own, as sharpening
  // it raises its noise as much as its detail.
  const auto sharpened = [&](const Image& slice, double blur_texels) {
    Image channels = btf_options.colour.Forward(slice);
    if (chromaticity) UndoGaussianBlur(&channels, blur_texels, /*first_channel=*/1);
    return channels;
  };
  const std::vector<int> partner =
      remove_noise ? NearestLightOfSameView(all, view_of, kNearHullDeg) : std::vector<int>(all.size(), -1);
  ParallelFor(0, int(all.size()), [&](int k) {
    if (cancelled) return;
    const Image slice = k < top_count ? Image() : read(k);
    const Image& measured = k < top_count ? images[k] : slice;
    if (errors[k].empty()) {
      const Image channels = sharpened(measured, blur[k]);
      stats[k] = ComputeSliceStatistics(channels, btf_options.statistics);
      if (partner[k] >= 0) {
        std::string ignored;  // the partner's own pass reports its errors
        double partner_blur = partner[k] < top_count ? blur[partner[k]] : 0.0;
        const Image loaded = partner[k] < top_count ? Image() : load(partner[k], &ignored, &partner_blur);
        const Image& other = partner[k] < top_count ? images[partner[k]] : loaded;  // top slices: no copy
        if (other.width() == measured.width() && other.height() == measured.height() &&
            other.channels() == measured.channels()) {
          const Image noise = NoiseDifference(channels, sharpened(other, partner_blur));
          RemoveNoiseVariance(&stats[k], ComputeSliceStatistics(noise, btf_options.statistics), /*first_channel=*/1);
        }
      }
      if (measured.channels() == 3) mean_rgb[k] = MeanRgb(measured);  // else unused (no colour)
    }
    if (!ReportProgress(progress, ++done, int(all.size()), "slice statistics")) cancelled = true;
  }, options.btf.num_threads);
  if (cancelled) return Status::Error("cancelled");

  std::vector<MeasuredView> measured(board_ids.size());
  std::vector<Image> top_slices;
  std::vector<Eigen::Vector3d> top_lights;
  for (size_t k = 0; k < all.size(); ++k) {
    if (!errors[k].empty()) {
      rep.skipped.push_back(all[k]->file.filename().string() + ": " + errors[k]);
      continue;
    }
    MeasuredView& v = measured[view_of[k]];
    v.view = views[view_of[k]];
    v.lights.push_back(all[k]->light);
    v.statistics.push_back(std::move(stats[k]));
    v.mean_rgb.push_back(mean_rgb[k]);
    if (view_of[k] == top) top_slices.push_back(std::move(images[k])), top_lights.push_back(all[k]->light);
    ++rep.slices_used;
  }
  std::vector<MeasuredView> usable;
  for (size_t b = 0; b < measured.size(); ++b) {
    if (int(measured[b].lights.size()) < kMinSlicesPerView) {
      rep.skipped.push_back("board " + std::to_string(board_ids[b]) + ": fewer than 3 usable slices, view not used");
      continue;
    }
    usable.push_back(std::move(measured[b]));
  }
  rep.views = int(usable.size());
  rep.top_lights = int(top_lights.size());
  auto btf = StatisticalBtf::Create(std::move(top_slices), std::move(top_lights), std::move(usable), btf_options);
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!btf.ok()) return Status::Error(index_json.string() + ": " + btf.status().message());
  return btf;
}

}  // namespace mesocap

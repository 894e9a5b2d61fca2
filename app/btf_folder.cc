#include "app/btf_folder.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <chrono>

#include "core/directions.h"
#include "core/image_io.h"
#include "core/parallel.h"
#include "core/provenance.h"
#include "core/session_layout.h"
#include "core/slice_attributes.h"
#include "core/text_format.h"

namespace mesocap::app {

namespace fs = std::filesystem;

std::vector<Eigen::Vector3d> GridDirections(const std::string& grid) {
  std::vector<Eigen::Vector3d> dirs;
  if (grid == "bonn") {
    dirs = BonnDirections();
  } else if (grid == "coarse") {
    for (const Eigen::Vector3d& d : BonnDirections()) {
      const Eigen::Vector2d a = AnglesDegFromDirection(d);
      const bool ring = std::abs(a.x()) < 0.5 || std::abs(a.x() - 30) < 0.5 || std::abs(a.x() - 60) < 0.5;
      const int ring_count = std::abs(a.x() - 30) < 0.5 ? 12 : 20;
      const int azimuth_step = int(std::lround(a.y() * ring_count / 360.0));
      if (ring && azimuth_step % 2 == 0) dirs.push_back(d);
    }
  }
  return dirs;
}

std::vector<DirectionPair> GridPairs(const std::string& grid) {
  const std::vector<Eigen::Vector3d> dirs = GridDirections(grid);
  std::vector<DirectionPair> pairs;
  for (const Eigen::Vector3d& view : dirs)
    for (const Eigen::Vector3d& light : dirs) {
      const Eigen::Vector2d i = AnglesDegFromDirection(light), o = AnglesDegFromDirection(view);
      pairs.push_back({i.x(), i.y(), o.x(), o.y()});
    }
  return pairs;
}

bool OnCoarseGrid(const Eigen::Vector3d& direction) {
  static const std::vector<Eigen::Vector3d> coarse = GridDirections("coarse");
  const double cos_tolerance = std::cos(DegToRad(0.5));
  return std::any_of(coarse.begin(), coarse.end(), [&](const Eigen::Vector3d& c) { return c.dot(direction) > cos_tolerance; });
}

std::string BtfSliceName(const DirectionPair& p) {
  return BtfFolder::SliceEntry(Format("ti%04.1f_pi%05.1f_to%04.1f_po%05.1f.exr", p[0], p[1], p[2], p[3]));
}

StatusOr<ReconstructedPairs> ReconstructPairs(const StatisticalBtf& btf, const std::vector<DirectionPair>& pairs,
                                              bool pixel_only, int num_threads, const fs::path& folder,
                                              const ProgressFn& progress) {
  std::error_code ec;
  fs::create_directories(BtfFolder{folder}.slices(), ec);
  if (ec) return Status::Error(folder.string() + ": cannot create: " + ec.message());
  ReconstructedPairs out;
  out.entries.resize(pairs.size());
  std::vector<std::string> errors(pairs.size());
  const auto start = std::chrono::steady_clock::now();
  std::atomic<int> done = 0;
  std::atomic<bool> cancelled = false;
  ParallelFor(0, int(pairs.size()), [&](int k) {
    if (cancelled) return;
    const DirectionPair& p = pairs[k];
    const Image slice = btf.Reconstruct(DirectionFromAnglesDeg(p[0], p[1]), DirectionFromAnglesDeg(p[2], p[3]));
    const std::string name = BtfSliceName(p);
    ImageWriteOptions w;
    w.format = PixelFormat::kHalf;
    SetSliceAngles(&w.attributes, p[0], p[1], p[2], p[3]);
    w.attributes["mesocap:quantity"] = kBtfSliceQuantity;
    w.attributes["mesocap:method"] = std::string(pixel_only ? "statistical (pixel histogram)" : "statistical (Ngan & Durand 2006)");
    if (Status st = WriteImage(folder / name, slice, w); !st.ok()) errors[k] = st.message();
    out.entries[k] = {{"file", name}, {"theta_i_deg", p[0]}, {"phi_i_deg", p[1]}, {"theta_o_deg", p[2]}, {"phi_o_deg", p[3]}};
    if (!ReportProgress(progress, ++done, int(pairs.size()), name)) cancelled = true;
  }, num_threads);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (const std::string& e : errors)
    if (!e.empty()) return Status::Error(e);
  if (cancelled) return Status::Cancelled();
  return out;
}

Json BtfIndexHeader(const StatisticalBtf& btf, const SliceSetReport& loaded) {
  return {{"format", "mesocap-btf"}, {"width", btf.width()}, {"height", btf.height()},
          {"views_measured", loaded.views}, {"top_board", loaded.top_board}, {"top_lights", loaded.top_lights},
          {"slices_used", loaded.slices_used}, {"chroma_from_top", loaded.chroma_from_top},
          {"white_lobe", btf.white_lobe().ToJson()}, {"mean_model", btf.mean_model_check().ToJson()},
          {"mirror_symmetry", btf.symmetry_check().ToJson()}, {"skipped", loaded.skipped}, {"warnings", loaded.warnings},
          {"seconds_statistics", loaded.seconds}};
}

StatusOr<BtfFolderReport> WriteBtfIndex(const fs::path& folder, Json header, const ReconstructedPairs& pairs,
                                        const Json& provenance_options) {
  BtfFolderReport report;
  report.seconds = pairs.seconds;
  report.slices = int(pairs.entries.size());
  report.ms_per_slice = pairs.entries.empty() ? 0 : 1000 * report.seconds / pairs.entries.size();
  header["seconds_reconstruct"] = report.seconds;
  header["ms_per_slice"] = report.ms_per_slice;
  header["slices"] = pairs.entries;
  header["provenance"] = MakeProvenance(provenance_options);
  MESOCAP_RETURN_IF_ERROR(WriteJsonFile(BtfFolder{folder}.index(), header));
  return report;
}

StatusOr<BtfFolderReport> WriteReconstructedBtf(const StatisticalBtf& btf, const SliceSetReport& loaded,
                                                const std::vector<DirectionPair>& pairs, bool pixel_only,
                                                int num_threads, const fs::path& folder,
                                                const Json& provenance_options, const ProgressFn& progress) {
  auto reconstructed = ReconstructPairs(btf, pairs, pixel_only, num_threads, folder, progress);
  if (!reconstructed.ok()) return reconstructed.status();
  return WriteBtfIndex(folder, BtfIndexHeader(btf, loaded), *reconstructed, provenance_options);
}

}  // namespace mesocap::app

#include "calib/resample.h"

#include "calib/occluders.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <set>
#include <tuple>

#include "core/atomic_file.h"
#include "core/chroma_detail.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "core/image_u8_io.h"
#include "core/parallel.h"
#include "core/provenance.h"
#include "core/session.h"
#include "core/session_layout.h"
#include "core/slice_attributes.h"
#include "core/text_format.h"

namespace mesocap {
namespace fs = std::filesystem;

std::string ResampleOptions::Check() const {
  if (slice_size < 8 || slice_size > 4096) return "--slice-size must be within 8 .. 4096";
  if (supersample < 0 || supersample > 16) return "supersample must be within 0 (automatic) .. 16";
  if (brdf_smoothing && !(brdf_smoothing_deg > 0 && brdf_smoothing_deg <= 90))
    return "the BRDF smoothing width must be within (0, 90] degrees";
  if (!(saturation_level > 0)) return "the saturation level must be positive";
  if (!(max_saturated_fraction >= 0 && max_saturated_fraction <= 1)) return "max saturated fraction must be within [0, 1]";
  if (visibility_grid < 2 || visibility_grid > 256) return "the visibility grid must be within 2 .. 256";
  return "";
}

Json ResampleOptions::ToJson() const {
  return {{"slice_size", slice_size},
          {"supersample", supersample},
          {"brdf_smoothing", brdf_smoothing},
          {"brdf_smoothing_deg", brdf_smoothing_deg},
          {"restore_chroma_detail", restore_chroma_detail},
          {"keep_mean_power_shots", keep_mean_power_shots},
          {"saturation_level", saturation_level},
          {"max_saturated_fraction", max_saturated_fraction},
          {"visibility_grid", visibility_grid}};  // not num_threads: it changes no output, and this is a cache key
}

Json SliceRecord::ToJson() const {
  return {{"file", file},
          {"board", board},
          {"shot", shot},
          {"theta_i_deg", theta_i_deg},
          {"phi_i_deg", phi_i_deg},
          {"theta_o_deg", theta_o_deg},
          {"phi_o_deg", phi_o_deg},
          {"light_distance_m", light_distance_m},
          {"texel_px", texel_px},
          {"light_spread_deg", light_spread_deg},
          {"mean", mean},
          {"scale", scale},
          {"saturated_fraction", saturated_fraction}};
}

Json ResampleReport::IndexJson() const {
  Json j = {{"format", "mesocap-slices"}, {"format_version", 1}, {"size", slice_size},
            {"units", "linear RGB radiance per unit irradiance perpendicular to the light"},
            {"frame", "patch: z = board normal, x right, y up; texel (i, j) centre at x = -P/2 + (i+0.5)P/N, y = P/2 - (j+0.5)P/N"},
            {"supersample", supersample}, {"seconds_total", seconds_total}, {"seconds_read", seconds_read},
            {"seconds_sample", seconds_sample}, {"seconds_write", seconds_write},
            {"scale_min", scale_min}, {"scale_max", scale_max}, {"scale_rms_deviation", scale_rms_deviation},
            {"chroma_subsampled_shots", chroma_subsampled_shots}, {"chroma_detail_restored", chroma_detail_restored}};
  j["slices"] = Json::array();
  for (const auto& s : slices) j["slices"].push_back(s.ToJson());
  j["skipped"] = Json::array();
  for (const auto& s : skipped) j["skipped"].push_back({{"board", s.board}, {"shot", s.shot}, {"reason", s.reason}});
  return j;
}

std::string ResampleReport::Brief() const {
  char buf[256];
  std::snprintf(buf, sizeof buf, "%zu slices of %dx%d, %zu skipped, BRDF smoothing scales %.3f .. %.3f (rms %.3f), %.1f s",
                slices.size(), slice_size, slice_size, skipped.size(), scale_min, scale_max, scale_rms_deviation,
                seconds_total);
  return buf;
}

namespace {

// Patch-frame centre of texel (i, j): docs/formats.md's grid (capture/btf_render.h's TexelCentre).
Eigen::Vector2d TexelCentreOf(int i, int j, int size, double patch_m) {
  return {-patch_m / 2 + (i + 0.5) * patch_m / size, patch_m / 2 - (j + 0.5) * patch_m / size};
}

}  // namespace

PatchSampler MakePatchSampler(const CameraModel& camera, const BoardPose& pose, double patch_m, int size,
                              int supersample) {
  PatchSampler s;
  s.board = pose.id;
  s.size = size;
  s.patch_m = patch_m;
  s.R = pose.R;
  s.t = pose.t;
  auto project = [&](double x, double y) { return camera.Project(pose.R * Eigen::Vector3d(x, y, 0) + pose.t); };
  // The footprint: the longest texel side over a grid of places on the patch.
  const double texel_m = patch_m / size;
  for (int a = 0; a <= 4; ++a)
    for (int b = 0; b <= 4; ++b) {
      const double x = patch_m * (a / 4.0 - 0.5), y = patch_m * (b / 4.0 - 0.5);
      const Eigen::Vector2d p = project(x, y);
      s.footprint_px = std::max({s.footprint_px, (project(x + texel_m, y) - p).norm(), (project(x, y + texel_m) - p).norm()});
    }
  const Eigen::Vector2d centre = project(0, 0), along_x = project(texel_m, 0) - centre, along_y = project(0, texel_m) - centre;
  s.texel_px = std::sqrt(std::abs(along_x.x() * along_y.y() - along_x.y() * along_y.x()));
  s.supersample = supersample > 0 ? supersample : std::clamp(int(std::ceil(s.footprint_px - 1e-6)), 1, 16);
  const int k = s.supersample;
  s.pixels.resize(size_t(size) * size * k * k);
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i)
      for (int b = 0; b < k; ++b)
        for (int a = 0; a < k; ++a) {
          // Sub-sample (a, b) of texel (i, j): the texel grid refined k times (TexelCentre's layout).
          const double x = -patch_m / 2 + (i + (a + 0.5) / k) * texel_m;
          const double y = patch_m / 2 - (j + (b + 0.5) / k) * texel_m;
          const Eigen::Vector2d px = project(x, y);
          // OpenCV pixel centres are integers; Image::SampleBilinear puts them at +0.5.
          s.pixels[((size_t(j) * size + i) * k + b) * k + a] = Eigen::Vector2f(float(px.x() + 0.5), float(px.y() + 0.5));
        }
  // SampleBilinear reads the pixels floor(x - 0.5) and the one after it.
  Eigen::Vector2f lo = s.pixels.front(), hi = s.pixels.front();
  for (const Eigen::Vector2f& p : s.pixels) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  s.reach = {int(std::floor(lo.x() - 0.5f)), int(std::floor(lo.y() - 0.5f)), int(std::floor(hi.x() - 0.5f)) + 2,
             int(std::floor(hi.y() - 0.5f)) + 2};
  return s;
}

Image ResamplePatch(const Image& photo, const PatchSampler& s, const Eigen::Vector3d& light_in_board,
                    double power_x_exposure, double saturation_level, int* saturated) {
  const int N = s.size, kk = s.supersample * s.supersample;
  const int C = photo.channels();
  Image out(N, N, 3);
  int n_saturated = 0;
  const float inv_k = 1.0f / kk;
  for (int j = 0; j < N; ++j)
    for (int i = 0; i < N; ++i) {
      const Eigen::Vector2f* px = &s.pixels[(size_t(j) * N + i) * kk];
      float sum[3] = {0, 0, 0}, peak = 0;
      for (int q = 0; q < kk; ++q) {
        float v[4] = {0, 0, 0, 0};
        photo.SampleBilinear(px[q].x(), px[q].y(), v);
        if (C < 3) v[1] = v[2] = v[0];
        for (int c = 0; c < 3; ++c) {
          sum[c] += v[c];
          peak = std::max(peak, v[c]);
        }
      }
      if (peak >= saturation_level) ++n_saturated;
      const Eigen::Vector2d xy = TexelCentreOf(i, j, N, s.patch_m);
      const double d2 = (light_in_board - Eigen::Vector3d(xy.x(), xy.y(), 0)).squaredNorm();
      const float norm = float(d2 / power_x_exposure) * inv_k;
      float* o = out.pixel(i, j);
      for (int c = 0; c < 3; ++c) o[c] = sum[c] * norm;
    }
  if (saturated) *saturated = n_saturated;
  return out;
}

Image AreaDownsample(const Image& image, int size) {
  MESOCAP_CHECK(size > 0 && image.width() == image.height() && image.width() % size == 0,
                "AreaDownsample needs a square image whose side is a multiple of the new size");
  const int f = image.width() / size, C = image.channels();
  Image out(size, size, C);
  for (int j = 0; j < size; ++j)
    for (int i = 0; i < size; ++i) {
      float* o = out.pixel(i, j);
      for (int y = 0; y < f; ++y)
        for (int x = 0; x < f; ++x) {
          const float* p = image.pixel(i * f + x, j * f + y);
          for (int c = 0; c < C; ++c) o[c] += p[c];
        }
      for (int c = 0; c < C; ++c) o[c] /= float(f * f);
    }
  return out;
}

std::vector<double> BrdfSmoothingScales(const std::vector<double>& mean, const std::vector<Eigen::Vector3d>& light,
                                        double sigma_deg) {
  const size_t n = mean.size();
  std::vector<double> brdf(n), scale(n, 1.0);
  for (size_t k = 0; k < n; ++k) brdf[k] = mean[k] / std::max(light[k].normalized().z(), 1e-3);
  const double inv_2s2 = 1.0 / (2 * sigma_deg * sigma_deg);
  for (size_t k = 0; k < n; ++k) {
    if (!(brdf[k] > 0)) continue;
    double sw = 0, swv = 0;
    for (size_t m = 0; m < n; ++m) {
      if (!(brdf[m] > 0)) continue;
      const double a = AngleBetweenDeg(light[k], light[m]);
      const double w = std::exp(-a * a * inv_2s2);
      sw += w;
      swv += w * brdf[m];
    }
    scale[k] = swv / sw / brdf[k];
  }
  return scale;
}

namespace {

// A shot as linear floats. A JPEG keeping its colour at half resolution gets the colour detail it
// dropped restored from its brightness (with `restore_chroma`): the tilted boards' patches span
// few pixels, and their slices would otherwise come out greyer than the material. Only where the
// patches read it (`patches`: their samplers' reach), 11% of a virtual session's shot.
StatusOr<Image> ReadShot(const fs::path& path, bool restore_chroma, std::span<const PixelRect> patches) {
  if (restore_chroma) {
    auto jpeg = JpegRowReader::Open(path, 3);
    if (!jpeg.ok()) return jpeg.status();
    if (*jpeg && (*jpeg)->channels() == 3 && ChromaDetailRestorable((*jpeg)->chroma_factors())) {
      auto srgb = (*jpeg)->ReadAll();
      if (!srgb.ok()) return srgb.status();
      return LinearWithChromaDetail(*srgb, (*jpeg)->chroma_factors(), 64, patches);
    }
  }
  return ReadImage(path);
}

std::string SliceFile(int board, const std::string& shot) {
  return SlicesFolder::SliceEntry(board, fs::path(shot).stem().string());
}

struct Plan {
  int board_index = 0;  // into calibration.boards / samplers
  int shot = 0;
  SliceRecord record;
  Eigen::Vector3d light_in_board;
  double power_x_exposure = 0;
};

}  // namespace

StatusOr<ResampleReport> ResampleSession(const ResampleOptions& options, const fs::path& session,
                                         const RigLayout& layout, const CalibrationResult& calibration,
                                         const ProgressFn& progress,
                                         const SliceFolderWriter& also_write) {
  const auto t0 = std::chrono::steady_clock::now();
  if (std::string why = options.Check(); !why.empty()) return Status::Error(why);
  std::string material;
  if (auto s = Session::Open(session); s.ok() && s->manifest().contains("material") && s->manifest()["material"].is_string())
    material = s->manifest()["material"].get<std::string>();

  ResampleReport report;
  report.slice_size = options.slice_size;
  const int nb = int(calibration.boards.size()), ns = int(calibration.shots.size());

  // Occluders and, per board, the texel -> pixel map and whether the camera sees the patch.
  const Occluders occ = Occluders::Of(calibration, layout);

  std::vector<PatchSampler> samplers(nb);
  std::vector<std::string> board_skip(nb);
  std::vector<double> patch_m(nb, 0);
  report.supersample.assign(nb, 0);
  for (int b = 0; b < nb; ++b) {
    const BoardPose& pose = calibration.boards[b];
    for (const auto& lb : layout.boards)
      if (lb.id == pose.id) patch_m[b] = lb.patch_m;
    if (!pose.found) {
      board_skip[b] = "board not posed: " + pose.why_not;
      continue;
    }
    if (!(patch_m[b] > 0)) {
      board_skip[b] = "board not in the rig layout";
      continue;
    }
    const Eigen::Vector3d camera_in_board = -pose.R.transpose() * pose.t;
    if (camera_in_board.z() <= 0) {
      board_skip[b] = "board faces away from the camera";
      continue;
    }
    std::string by;
    const double hidden = BlockedFraction(occ, pose, patch_m[b], options.visibility_grid, Eigen::Vector3d::Zero(), &by);
    if (hidden > 0) {
      board_skip[b] = Format("patch hidden from the camera by %s (%.0f%% of it)", by.c_str(), 100 * hidden);
      continue;
    }
    samplers[b] = MakePatchSampler(calibration.camera, pose, patch_m[b], options.slice_size, options.supersample);
    bool inside = true;
    for (const Eigen::Vector2f& p : samplers[b].pixels)
      inside = inside && p.x() >= 0.5f && p.y() >= 0.5f && p.x() <= calibration.camera.width - 0.5f &&
               p.y() <= calibration.camera.height - 0.5f;
    if (!inside) {
      board_skip[b] = "patch not wholly inside the image";
      samplers[b] = PatchSampler{};
      continue;
    }
    report.supersample[b] = samplers[b].supersample;
  }

  // Every (board, shot): resample or say why not.
  std::vector<std::vector<Plan>> plans(ns);  // per shot
  for (int s = 0; s < ns; ++s) {
    const ShotCalibration& sc = calibration.shots[s];
    std::string shot_skip;
    if (!sc.light.ok) shot_skip = "no flash position: " + sc.flag;
    else if (!(sc.power_x_exposure > 0)) shot_skip = "no flash power";
    else if (!sc.flag.empty() && !(options.keep_mean_power_shots && sc.flag.find("mean power used") != std::string::npos))
      shot_skip = "shot flagged: " + sc.flag;
    for (int b = 0; b < nb; ++b) {
      const BoardPose& pose = calibration.boards[b];
      auto skip = [&](const std::string& why) { report.skipped.push_back({pose.id, sc.file, why}); };
      if (!board_skip[b].empty()) {
        skip(board_skip[b]);
        continue;
      }
      if (!shot_skip.empty()) {
        skip(shot_skip);
        continue;
      }
      const Eigen::Vector3d light_in_board = pose.R.transpose() * (sc.light.light_m - pose.t);
      const Eigen::Vector3d camera_in_board = -pose.R.transpose() * pose.t;
      const Eigen::Vector2d in = AnglesDegFromDirection(light_in_board), out = AnglesDegFromDirection(camera_in_board);
      if (in.x() >= 90) {
        skip(Format("light behind the board (theta_i %.1f deg)", in.x()));
        continue;
      }
      std::string by;
      const double shadowed = BlockedFraction(occ, pose, patch_m[b], options.visibility_grid, sc.light.light_m, &by);
      if (shadowed > 0) {
        skip(Format("patch shadowed by %s (%.0f%% of it)", by.c_str(), 100 * shadowed));
        continue;
      }
      Plan p;
      p.board_index = b;
      p.shot = s;
      p.light_in_board = light_in_board;
      p.power_x_exposure = sc.power_x_exposure;
      SliceRecord& r = p.record;
      r.file = SliceFile(pose.id, sc.file);
      r.board = pose.id;
      r.shot = sc.file;
      r.theta_i_deg = in.x();
      r.phi_i_deg = in.y();
      r.theta_o_deg = out.x();
      r.phi_o_deg = out.y();
      r.light_distance_m = light_in_board.norm();
      r.texel_px = samplers[b].texel_px;
      const double h = patch_m[b] / 2;
      for (const Eigen::Vector3d& corner : {Eigen::Vector3d(-h, -h, 0), Eigen::Vector3d(h, -h, 0),
                                           Eigen::Vector3d(h, h, 0), Eigen::Vector3d(-h, h, 0)})
        r.light_spread_deg = std::max(r.light_spread_deg, AngleBetweenDeg(light_in_board, light_in_board - corner));
      plans[s].push_back(p);
    }
  }

  // Resampling, one photo per thread at a time. With smoothing, a first pass finds the slice
  // means (photos are cheap to decode again; slices are too big to keep).
  const int passes = options.brdf_smoothing ? 2 : 1;
  // A re-run builds a fresh slices/ beside the old one and swaps it in at the end: a crash never
  // leaves an index.json describing slices half overwritten, and no slice of an earlier run is
  // taken for a current one.
  auto staging = StagingFolder::Begin(SessionLayout(session).slices().root);
  if (!staging.ok()) return staging.status();
  const fs::path slices_dir = staging->path();
  std::atomic<int> done{0};
  std::atomic<bool> cancelled{false};
  std::vector<std::string> shot_error(ns);
  std::vector<std::vector<std::string>> slice_error(ns);
  std::atomic<int64_t> ns_read{0}, ns_sample{0}, ns_write{0};
  auto since = [](std::chrono::steady_clock::time_point t) {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t).count();
  };
  auto run_pass = [&](bool write) {
    ParallelFor(0, ns, [&](int s) {
      if (plans[s].empty() || cancelled || !shot_error[s].empty()) {
        if (!ReportProgress(progress, ++done, passes * ns, calibration.shots[s].file)) cancelled = true;
        return;
      }
      auto t_read = std::chrono::steady_clock::now();
      std::vector<PixelRect> patches;
      for (const Plan& p : plans[s]) patches.push_back(samplers[p.board_index].reach);
      auto photo = ReadShot(session / calibration.shots[s].file, options.restore_chroma_detail, patches);
      ns_read += since(t_read);
      if (!photo.ok()) {
        shot_error[s] = photo.status().message();
        return;
      }
      slice_error[s].assign(plans[s].size(), "");
      for (size_t k = 0; k < plans[s].size(); ++k) {
        Plan& p = plans[s][k];
        int saturated = 0;
        const auto t_sample = std::chrono::steady_clock::now();
        Image slice = ResamplePatch(*photo, samplers[p.board_index], p.light_in_board, p.power_x_exposure,
                                    options.saturation_level, &saturated);
        ns_sample += since(t_sample);
        if (!write) {
          double sum = 0;
          for (size_t i = 0; i < slice.size(); ++i) sum += slice.data()[i];
          p.record.mean = sum / slice.size();
          p.record.saturated_fraction = double(saturated) / slice.pixel_count();
          continue;
        }
        if (passes == 1) {
          double sum = 0;
          for (size_t i = 0; i < slice.size(); ++i) sum += slice.data()[i];
          p.record.mean = sum / slice.size();
          p.record.saturated_fraction = double(saturated) / slice.pixel_count();
        }
        if (p.record.saturated_fraction > options.max_saturated_fraction) continue;  // listed as skipped below
        if (p.record.scale != 1.0)
          for (size_t i = 0; i < slice.size(); ++i) slice.data()[i] *= float(p.record.scale);
        ImageWriteOptions wo;
        wo.format = PixelFormat::kHalf;
        wo.exr_compression = "piz";  // as small as zip on noisy photographs, several times faster
        const SliceRecord& r = p.record;
        SetSliceAngles(&wo.attributes, r.theta_i_deg, r.phi_i_deg, r.theta_o_deg, r.phi_o_deg);
        wo.attributes.insert({{"mesocap:patch_m", float(patch_m[p.board_index])}, {"mesocap:material", material},
                              {"mesocap:board", r.board}, {"mesocap:shot", r.shot}, {"mesocap:scale", float(r.scale)},
                              {"mesocap:light_distance_m", float(r.light_distance_m)}});
        const auto t_write = std::chrono::steady_clock::now();
        std::error_code ec;
        fs::create_directories((slices_dir / r.file).parent_path(), ec);
        if (Status st = WriteImage(slices_dir / r.file, slice, wo); !st.ok()) slice_error[s][k] = st.message();
        ns_write += since(t_write);
      }
      if (!ReportProgress(progress, ++done, passes * ns, calibration.shots[s].file)) cancelled = true;
    }, options.num_threads);
  };

  if (options.brdf_smoothing) {
    run_pass(false);
    if (cancelled) return Status::Cancelled();
    // Per view (board), over the slices that will be written.
    for (int b = 0; b < nb; ++b) {
      std::vector<Plan*> members;
      for (int s = 0; s < ns; ++s)
        for (Plan& p : plans[s])
          if (p.board_index == b && shot_error[s].empty() &&
              p.record.saturated_fraction <= options.max_saturated_fraction)
            members.push_back(&p);
      std::vector<double> mean;
      std::vector<Eigen::Vector3d> light;
      for (const Plan* p : members) {
        mean.push_back(p->record.mean);
        light.push_back(p->light_in_board.normalized());
      }
      const std::vector<double> scale = BrdfSmoothingScales(mean, light, options.brdf_smoothing_deg);
      for (size_t k = 0; k < members.size(); ++k) members[k]->record.scale = scale[k];
    }
  }
  run_pass(true);
  if (cancelled) return Status::Cancelled();

  for (int s = 0; s < ns; ++s)
    for (size_t k = 0; k < plans[s].size(); ++k) {
      const SliceRecord& r = plans[s][k].record;
      if (!shot_error[s].empty()) report.skipped.push_back({r.board, r.shot, "unreadable: " + shot_error[s]});
      else if (r.saturated_fraction > options.max_saturated_fraction)
        report.skipped.push_back({r.board, r.shot, Format("%.1f%% of the patch saturated", 100 * r.saturated_fraction)});
      else if (!slice_error[s][k].empty()) report.skipped.push_back({r.board, r.shot, "not written: " + slice_error[s][k]});
      else report.slices.push_back(r);
    }
  std::sort(report.slices.begin(), report.slices.end(),
            [](const SliceRecord& a, const SliceRecord& b) { return std::tie(a.board, a.shot) < std::tie(b.board, b.shot); });
  std::sort(report.skipped.begin(), report.skipped.end(),
            [](const SkippedSlice& a, const SkippedSlice& b) { return std::tie(a.board, a.shot) < std::tie(b.board, b.shot); });
  if (!report.slices.empty()) {
    report.scale_min = report.scale_max = report.slices.front().scale;
    double sq = 0;
    for (const auto& r : report.slices) {
      report.scale_min = std::min(report.scale_min, r.scale);
      report.scale_max = std::max(report.scale_max, r.scale);
      sq += (r.scale - 1) * (r.scale - 1);
    }
    report.scale_rms_deviation = std::sqrt(sq / report.slices.size());
    // Judged by the first slice's shot, as ReadShot treated it.
    auto first = JpegRowReader::Open(session / report.slices.front().shot);
    report.chroma_subsampled_shots = first.ok() && *first && (*first)->chroma_subsampled();
    report.chroma_detail_restored = report.chroma_subsampled_shots && options.restore_chroma_detail &&
                                    ChromaDetailRestorable((*first)->chroma_factors());
  }

  report.seconds_read = 1e-9 * double(ns_read);
  report.seconds_sample = 1e-9 * double(ns_sample);
  report.seconds_write = 1e-9 * double(ns_write);
  report.seconds_total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  Json index = report.IndexJson();
  index["material"] = material;
  index["provenance"] = MakeProvenance(options.ToJson());
  if (Status st = WriteJsonFile(SlicesFolder{slices_dir}.index(), index); !st.ok()) return st;
  if (also_write)
    if (Status st = also_write(slices_dir, report); !st.ok()) return st;
  if (Status st = staging->Publish(/*replace=*/true); !st.ok()) return st;
  return report;
}

}  // namespace mesocap

// mesocap fit-ptm: fit a polynomial texture map (reconstruct/ptm.h) to an RTI capture given as a
// .lp light file and its photos, and write it as HP's .ptm (formats/ptm_file.h) plus a JSON report.
#include "app/fit_ptm_args.h"

#include <sys/resource.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <spdlog/spdlog.h>

#include "app/commands.h"
#include "app/photo_rows.h"
#include "core/atomic_file.h"
#include "core/cancel.h"
#include "core/image_io.h"
#include "core/image_u8_io.h"
#include "core/json.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "core/provenance.h"
#include "core/resource_usage.h"
#include "core/scratch_file.h"
#include "formats/lp_file.h"
#include "formats/ptm_file.h"
#include "reconstruct/ptm.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;

// 16-bit PNG/TIFF hold linear values, so writing with kUint16Linear stores the values as they are.
ImageWriteOptions StoredValueOptions(const fs::path& path) {
  ImageWriteOptions o;
  o.format = DefaultFormatFor(path);
  return o;
}

struct PhaseSeconds {
  double decode = 0, fit = 0, decode_cpu = 0, fit_cpu = 0;
};

// Adds the wall and process CPU seconds of its scope to *wall and *cpu.
class PhaseTimer {
 public:
  PhaseTimer(double* wall, double* cpu)
      : wall_(wall), cpu_(cpu), start_(std::chrono::steady_clock::now()), cpu_start_(ProcessCpuSeconds()) {}
  ~PhaseTimer() {
    *wall_ += SecondsSince(start_);
    *cpu_ += ProcessCpuSeconds() - cpu_start_;
  }
  PhaseTimer(const PhaseTimer&) = delete;
  PhaseTimer& operator=(const PhaseTimer&) = delete;

 private:
  double *wall_, *cpu_;
  std::chrono::steady_clock::time_point start_;
  double cpu_start_;
};

// Every photo the size and channel count of the first; the error names both files.
Status CheckSameShape(const std::vector<LpEntry>& entries, const std::function<std::array<int, 3>(int)>& shape_of) {
  const auto first = shape_of(0);
  for (int i = 1; i < int(entries.size()); ++i) {
    const auto other = shape_of(i);
    if (other[0] != first[0] || other[1] != first[1])
      return Status::Error("images differ in size: " + entries[0].image.string() + " is " + std::to_string(first[0]) + "x" +
                           std::to_string(first[1]) + " but " + entries[size_t(i)].image.string() + " is " +
                           std::to_string(other[0]) + "x" + std::to_string(other[1]));
    if (other[2] != first[2])
      return Status::Error("images differ in channel count: " + entries[0].image.string() + " and " +
                           entries[size_t(i)].image.string());
  }
  return Status::Ok();
}

// Every photo's decoder keeps its file open: raises the soft limit on open files as far as the
// hard limit allows; false if that is still fewer than `count` plus a margin.
bool AllowOpenFiles(int count) {
  rlimit limit{};
  if (getrlimit(RLIMIT_NOFILE, &limit) != 0) return false;
  const rlim_t wanted = rlim_t(count) + 64;
  if (limit.rlim_cur >= wanted) return true;
  if (limit.rlim_max != RLIM_INFINITY && limit.rlim_max < wanted) return false;
  limit.rlim_cur = wanted;
  return setrlimit(RLIMIT_NOFILE, &limit) == 0;
}

// Busy seconds of the tasks of one phase, summed over threads (atomic: tasks of both phases run at
// once).
class BusySeconds {
 public:
  template <typename Fn>
  void Time(Fn&& fn) {
    const auto start = std::chrono::steady_clock::now();
    fn();
    nanoseconds_ += std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start).count();
  }
  double seconds() const { return double(nanoseconds_.load()) * 1e-9; }

 private:
  std::atomic<int64_t> nanoseconds_{0};
};

// Decodes bands of rows of every photo, fits them, and parks the fitted rows in a scratch file
// (beside the output: row y's coefficients, then the LRGB colours), returned as the .ptm writer
// reads them, with their coefficient range; the normals and albedo, when asked for, are taken
// from each fitted band. Band k + 1 is decoded while band k is fitted, as tasks of one parallel
// loop, so no core waits at a barrier between decoding and fitting. Nothing grows with the image
// but the maps asked for: fresh memory costs page faults, the scratch file only page-cache copies.
StatusOr<PtmRowSource> FitStreamingJpegs(std::vector<PhotoRows>& readers,
                                       const std::vector<LpEntry>& entries, const std::vector<Eigen::Vector3d>& lights,
                                       const PtmFitOptions& fit, const fs::path& scratch_folder, bool want_maps,
                                       ProgressBar& bar, PtmFitReport* report, PtmNormalsAlbedo* maps,
                                       PhaseSeconds* seconds) {
  const int n = int(readers.size());
  MESOCAP_RETURN_IF_ERROR(CheckSameShape(entries, [&](int i) {
    return std::array<int, 3>{readers[size_t(i)].width(), readers[size_t(i)].height(), readers[size_t(i)].channels()};
  }));
  const int width = readers[0].width(), height = readers[0].height(), channels = readers[0].channels();
  auto fitter = PtmRowFitter::Create(lights, width, height, channels, fit);
  if (!fitter.ok()) return fitter.status();
  auto created = ScratchFile::Create(scratch_folder);
  if (!created.ok()) return created.status();
  const auto scratch = std::make_shared<const ScratchFile>(std::move(*created));
  // 16 rows (a 4:2:0 JPEG's MCU row) of 36 photos of 2000 pixels: 3.5 MB a band, two bands (the
  // one being fitted and the one being decoded) in cache.
  constexpr int kBandRows = 16;
  const int bands = (height + kBandRows - 1) / kBandRows;
  const size_t row_bytes = size_t(width) * channels;
  std::array<std::vector<std::vector<uint8_t>>, 2> band_buffers;
  for (auto& buffers : band_buffers) buffers.assign(size_t(n), std::vector<uint8_t>(kBandRows * row_bytes));
  const auto rows_of_band = [&](int band) { return std::min(kBandRows, height - band * kBandRows); };
  Ptm fitted = fitter->NewRows(std::min(kBandRows, height));
  const bool lrgb = fit.format == PtmFormat::kLrgb;
  const size_t coefficient_row_floats = size_t(width) * fitted.coefficients.channels(), rgb_row_floats = size_t(width) * 3;
  const auto coefficient_offset = [=](int y) { return uint64_t(y) * coefficient_row_floats * sizeof(float); };
  const auto rgb_offset = [=](int y) { return (uint64_t(height) * coefficient_row_floats + uint64_t(y) * rgb_row_floats) * sizeof(float); };
  if (want_maps) *maps = {Image::Uninitialized(width, height, 3), Image::Uninitialized(width, height, 3)};
  std::vector<CoefficientRange> row_ranges(static_cast<size_t>(height));
  std::vector<std::string> decode_errors(static_cast<size_t>(n)), row_errors(static_cast<size_t>(height));
  BusySeconds decode_busy, fit_busy;
  const auto decode = [&](int band, int i) {
    decode_busy.Time([&] {
      const int rows = rows_of_band(band);
      uint8_t* row_pointers[kBandRows];
      uint8_t* photo_band = band_buffers[size_t(band % 2)][size_t(i)].data();
      for (int r = 0; r < rows; ++r) row_pointers[r] = photo_band + size_t(r) * row_bytes;
      if (Status st = readers[size_t(i)].ReadRows(rows, row_pointers); !st.ok()) decode_errors[size_t(i)] = st.message();
    });
  };
  const auto fit_row = [&](int band, int y) {
    fit_busy.Time([&] {
      const int y0 = band * kBandRows;
      const auto& buffers = band_buffers[size_t(band % 2)];
      fitter->FitRow(
          y, y0,
          std::function<const uint8_t*(int, int)>(
              [&](int i, int row) -> const uint8_t* { return buffers[size_t(i)].data() + size_t(row - y0) * row_bytes; }),
          &fitted);
      const float* coefficients = fitted.coefficients.row(y - y0);
      row_ranges[size_t(y)] = RowCoefficientRange(coefficients, int(coefficient_row_floats));
      Status st = scratch->Write(coefficient_offset(y), coefficients, coefficient_row_floats * sizeof(float));
      if (st.ok() && lrgb) st = scratch->Write(rgb_offset(y), fitted.rgb.row(y - y0), rgb_row_floats * sizeof(float));
      if (!st.ok()) row_errors[size_t(y)] = st.message();
    });
  };
  const auto first_error = [](const std::vector<std::string>& errors) {
    for (const std::string& error : errors)
      if (!error.empty()) return error;
    return std::string();
  };
  ParallelFor(0, n, [&](int i) { decode(0, i); }, fit.num_threads);
  for (int band = 0; band < bands; ++band) {
    if (std::string error = first_error(decode_errors); !error.empty()) return Status::Error(error);
    const int y0 = band * kBandRows, rows = rows_of_band(band);
    const int decodes = band + 1 < bands ? n : 0;
    if (fitted.height() != rows) fitted = fitter->NewRows(rows);  // the last, shorter band
    // The decoding tasks come first: the loop's halves split between the cores mix both kinds.
    ParallelFor(
        0, decodes + rows, [&](int task) { task < decodes ? decode(band + 1, task) : fit_row(band, y0 + task - decodes); },
        fit.num_threads);
    if (std::string error = first_error(row_errors); !error.empty()) return Status::Error(error);
    if (want_maps) {
      const PtmNormalsAlbedo band_maps = PtmNormalsAndAlbedo(fitted, fit.num_threads);
      for (int r = 0; r < rows; ++r) {
        std::memcpy(maps->normals.row(y0 + r), band_maps.normals.row(r), rgb_row_floats * sizeof(float));
        std::memcpy(maps->albedo.row(y0 + r), band_maps.albedo.row(r), rgb_row_floats * sizeof(float));
      }
    }
    if (!bar.Update(y0 + rows, height + 1, "rows")) return Status::Cancelled();  // Ctrl-C: the scratch file goes too
  }
  // The phases overlap: each is reported as its busy core-seconds, and as those shared over the
  // threads (what it adds to the wall clock).
  const double threads = EffectiveThreadCount(fit.num_threads);
  seconds->decode += decode_busy.seconds() / threads;
  seconds->decode_cpu += decode_busy.seconds();
  seconds->fit += fit_busy.seconds() / threads;
  seconds->fit_cpu += fit_busy.seconds();
  readers.clear();  // the files
  fitter->Report(report);
  PtmRowSource parked{fit.format, width, height, CoefficientRange::Empty(), {}, {}};
  for (const CoefficientRange& range : row_ranges) parked.range.Include(range);
  const auto read_back = [scratch](uint64_t offset, size_t floats, std::vector<float>* buffer) -> StatusOr<const float*> {
    buffer->resize(floats);
    MESOCAP_RETURN_IF_ERROR(scratch->Read(offset, buffer->data(), floats * sizeof(float)));
    return buffer->data();
  };
  parked.coefficients = [=](int y, std::vector<float>* buffer) {
    return read_back(coefficient_offset(y), coefficient_row_floats, buffer);
  };
  parked.rgb = [=](int y, std::vector<float>* buffer) { return read_back(rgb_offset(y), rgb_row_floats, buffer); };
  return parked;
}

// Any other photos (PNG, TIFF, 16-bit, --linearize): decoded whole in parallel, then fitted.
// 8-bit photos fitted as stored stay bytes (36 x 3 MP: 324 MB, not 1.3 GB as floats).
StatusOr<Ptm> FitWholePhotos(const std::vector<LpEntry>& entries, const std::vector<Eigen::Vector3d>& lights,
                             const PtmFitOptions& fit, const FitPtmArgs& args, ProgressBar& bar, PtmFitReport* report,
                             PhaseSeconds* seconds, std::string* read_path) {
  const int n = int(entries.size());
  bool eight_bit = !args.linearize;
  for (int i = 0; i < n && eight_bit; ++i) {
    auto info = ReadImageInfo(entries[size_t(i)].image);
    eight_bit = info.ok() && info->bits_per_sample == 8;
  }
  *read_path = eight_bit ? "8-bit (decoded to bytes, fitted from bytes)" : "float";
  std::vector<Image> images(eight_bit ? 0 : size_t(n));
  std::vector<ImageU8> images_u8(eight_bit ? size_t(n) : 0);
  std::vector<std::string> errors(entries.size());
  std::atomic<int> decoded{0};
  {
    PhaseTimer timer(&seconds->decode, &seconds->decode_cpu);
    ParallelFor(
        0, n,
        [&](int i) {
          if (CancelRequested()) return;  // Ctrl-C: the photos not yet decoded are left
          const fs::path& file = entries[size_t(i)].image;
          if (eight_bit) {
            auto image = ReadImageU8(file, 3);
            if (image.ok()) images_u8[size_t(i)] = std::move(*image);
            else errors[size_t(i)] = image.status().message();
          } else {
            auto image = ReadImage(file, {.linearize = args.linearize, .max_channels = 3});
            if (image.ok()) images[size_t(i)] = std::move(*image);
            else errors[size_t(i)] = image.status().message();
          }
          bar.Update(++decoded, n + 1, file.filename().string());
        },
        args.threads);
  }
  if (CancelRequested()) return Status::Cancelled();
  for (const std::string& error : errors)
    if (!error.empty()) return Status::Error(error);
  MESOCAP_RETURN_IF_ERROR(CheckSameShape(entries, [&](int i) {
    return eight_bit ? std::array<int, 3>{images_u8[size_t(i)].width(), images_u8[size_t(i)].height(), images_u8[size_t(i)].channels()}
                     : std::array<int, 3>{images[size_t(i)].width(), images[size_t(i)].height(), images[size_t(i)].channels()};
  }));
  PhaseTimer timer(&seconds->fit, &seconds->fit_cpu);
  return eight_bit ? FitPtm(images_u8, lights, fit, report) : FitPtm(images, lights, fit, report);
}

}  // namespace

int RunFitPtm(const FitPtmArgs& args) {
  const std::string verb = "fit-ptm";
  PtmFitOptions fit;
  if (!StringToPtmFormat(args.format, &fit.format))
    return Fail(verb, "--format must be lrgb or rgb, not '" + args.format + "'", kExitUsage);
  if (args.threads == 0 || args.threads < -1)
    return Fail(verb, "--threads must be a positive number (or -1 for all cores)", kExitUsage);
  fit.num_threads = args.threads;
  const fs::path out = args.out;
  if (out.extension() != ".ptm") return Fail(verb, "--out must name a .ptm file: " + args.out, kExitUsage);
  fs::path json_path = out;
  json_path.replace_extension(".json");
  const auto start = std::chrono::steady_clock::now();

  // Lights first: a bad light set is refused before any photo is decoded.
  auto entries = ReadLpFile(args.lp, /*require_images_exist=*/true);
  if (!entries.ok()) return Fail(verb, entries.status());
  std::vector<Eigen::Vector3d> lights;
  for (const LpEntry& e : *entries) lights.push_back(e.light_dir);
  PtmLightCheck light_check;
  if (Status s = ValidatePtmLights(lights, fit, &light_check); !s.ok())
    return Fail(verb, args.lp + ": " + s.message());
  for (const std::string& warning : light_check.warnings) spdlog::warn("{}: {}", args.lp, warning);

  const int n = int(entries->size());
  ProgressBar bar("fit-ptm", !args.no_progress);
  PtmFitReport report;
  PhaseSeconds seconds;
  std::string read_path;
  StatusOr<Ptm> ptm = Status::Error("no fit");  // photos fitted whole
  StatusOr<PtmRowSource> parked = Status::Error("no fit");  // JPEGs streamed
  PtmNormalsAlbedo maps;
  const bool want_maps = !args.normals.empty() || !args.albedo.empty();
  // Reading the files and their JPEG headers counts as decoding.
  StatusOr<std::vector<PhotoRows>> readers = std::vector<PhotoRows>();
  if (!args.linearize && AllowOpenFiles(n)) {
    PhaseTimer timer(&seconds.decode, &seconds.decode_cpu);
    readers = OpenPhotoRows(*entries, out.parent_path(), args.threads);
  }
  if (!readers.ok()) return Fail(verb, readers.status());
  const bool streamed = !readers->empty();
  if (streamed) {
    const auto parked_photos = std::count_if(readers->begin(), readers->end(), [](const PhotoRows& p) { return p.parked(); });
    read_path = "8-bit JPEG streamed in bands of rows (decoded and fitted band by band)";
    if (parked_photos > 0)
      read_path += "; " + std::to_string(parked_photos) + " progressive decoded whole first, read back from a scratch file";
    parked = FitStreamingJpegs(*readers, *entries, lights, fit, out.parent_path(), want_maps, bar, &report, &maps,
                               &seconds);
    if (!parked.ok()) return Fail(verb, parked.status());
  } else {
    ptm = FitWholePhotos(*entries, lights, fit, args, bar, &report, &seconds, &read_path);
    if (!ptm.ok()) return Fail(verb, ptm.status());
    if (want_maps) maps = PtmNormalsAndAlbedo(*ptm, args.threads);
  }
  bar.Update(n + 1, n + 1, "fit");
  const double decode_seconds = seconds.decode, fit_seconds = seconds.fit;
  const double decode_cpu_seconds = seconds.decode_cpu, fit_cpu_seconds = seconds.fit_cpu;
  // Normals map [-1, 1] to [0, 1] as normal maps do.
  for (size_t k = 0; k < maps.normals.size(); ++k) maps.normals.data()[k] = 0.5f * (maps.normals.data()[k] + 1.f);

  // Write: the .ptm, the optional maps, then the report; all appear together or none does.
  const auto write_start = std::chrono::steady_clock::now();
  const double write_cpu_start = ProcessCpuSeconds();
  OutputFileSet outputs;
  PtmQuantization quantization;
  if (Status s = outputs.Stage(out, [&](const fs::path& temp) {
        return streamed ? WritePtmFile(temp, *parked, {}, &quantization) : WritePtmFile(temp, *ptm, {}, &quantization);
      });
      !s.ok())
    return Fail(verb, s);
  for (const auto& named_map : {std::pair{args.normals, &maps.normals}, std::pair{args.albedo, &maps.albedo}}) {
    const auto& [path, map] = named_map;  // (clang 14 cannot capture a structured binding)
    if (path.empty()) continue;
    const auto write_map = [&named_map](const fs::path& temp) {
      return WriteImage(temp, *named_map.second, StoredValueOptions(named_map.first));
    };
    if (Status s = outputs.Stage(path, write_map); !s.ok()) return Fail(verb, s);
  }
  const double write_seconds = SecondsSince(write_start);
  const double write_cpu_seconds = ProcessCpuSeconds() - write_cpu_start;
  const double total_seconds = SecondsSince(start);

  Json options = {{"lp", args.lp},           {"out", args.out},
                  {"format", args.format},   {"normals", args.normals},
                  {"albedo", args.albedo},   {"linearize", args.linearize},
                  {"threads", args.threads}, {"threads_used", EffectiveThreadCount(args.threads)}};
  Json j;
  j["provenance"] = MakeProvenance(options);
  j["fit"] = {{"format", PtmFormatToString(fit.format)},
              {"num_lights", report.num_lights},
              {"width", report.width},
              {"height", report.height},
              {"light_matrix_condition", report.light_matrix_condition},
              {"warnings", report.warnings},
              {"rms_residual", report.rms_residual},
              {"units", args.linearize ? "linear" : "stored values (as read, not linearised)"}};
  j["quantization"] = {{"scale", quantization.scale}, {"bias", quantization.bias}};
  j["timing"] = {{"decode_seconds", decode_seconds},
                 {"fit_seconds", fit_seconds},
                 {"fit_seconds_core", report.fit_seconds},
                 {"write_seconds", write_seconds},
                 {"total_seconds", total_seconds},
                 {"decode_share", total_seconds > 0 ? decode_seconds / total_seconds : 0.0},
                 {"decode_cpu_seconds", decode_cpu_seconds},
                 {"fit_cpu_seconds", fit_cpu_seconds},
                 {"write_cpu_seconds", write_cpu_seconds},
                 {"megapixel_images_per_second",
                  total_seconds > 0 ? double(report.width) * report.height * n / 1e6 / total_seconds : 0.0}};
  j["read_path"] = read_path;
  j["memory_peak_mib"] = PeakMemoryMiB();
  j["inputs"] = Json::array();
  for (const LpEntry& e : *entries) j["inputs"].push_back({{"image", e.image.string()}, {"light", ToJson(e.light_dir)}});
  if (Status s = outputs.Stage(json_path, [&](const fs::path& temp) { return WriteJsonFile(temp, j); }); !s.ok())
    return Fail(verb, s);
  if (Status s = outputs.Commit(); !s.ok()) return Fail(verb, s);

  std::printf("%s: %s %dx%d from %d lights, rms residual %.5f; decode %.3f s, fit %.3f s, write %.3f s, "
              "total %.3f s\n",
              out.string().c_str(), PtmFormatToString(fit.format).c_str(), report.width, report.height,
              report.num_lights, report.rms_residual, decode_seconds, fit_seconds, write_seconds, total_seconds);
  // A .ptm has no field for its values' space: say it where the user sees it (and in the report).
  if (args.linearize)
    std::printf("%s holds linear values: relight it with `mesocap relight --linear` (viewers show it dark)\n",
                out.string().c_str());
  return kExitOk;
}
}  // namespace mesocap::app

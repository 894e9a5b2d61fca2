// mesocap fit-ptm: fit a polynomial texture map (reconstruct/ptm.h) to an RTI capture given as a
// .lp light file and its photos, and write it as HP's .ptm (export/ptm_file.h) plus a JSON report.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "app/commands.h"
#include "core/image_io.h"
#include "core/json.h"
#include "core/parallel.h"
#include "core/progress.h"
#include "core/provenance.h"
#include "export/lp_file.h"
#include "export/ptm_file.h"
#include "reconstruct/ptm.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;

struct FitPtmArgs {
  std::string lp;
  std::string out;
  std::string format = "lrgb";
  std::string normals;
  std::string albedo;
  bool linearize = false;
  int threads = -1;
  bool no_progress = false;
};

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// 16-bit PNG/TIFF hold linear values, so writing with kUint16Linear stores the values as they are.
ImageWriteOptions StoredValueOptions(const fs::path& path) {
  ImageWriteOptions o;
  o.format = DefaultFormatFor(path);
  return o;
}

int Run(const FitPtmArgs& args) {
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
  if (!entries.ok()) return Fail(verb, entries.status().message());
  std::vector<Eigen::Vector3d> lights;
  for (const LpEntry& e : *entries) lights.push_back(e.light_dir);
  double condition = 0;
  if (Status s = ValidatePtmLights(lights, fit, &condition); !s.ok())
    return Fail(verb, args.lp + ": " + s.message());

  // Decode all photos in parallel (decoding dominates the fitter's time otherwise).
  const int n = int(entries->size());
  std::vector<Image> images(n);
  std::vector<std::string> errors(n);
  ProgressBar bar("fit-ptm", !args.no_progress);
  std::mutex bar_mutex;
  std::atomic<int> decoded{0};
  ImageReadOptions read;
  read.linearize = args.linearize;
  read.max_channels = 3;
  const auto decode_start = std::chrono::steady_clock::now();
  ParallelFor(
      0, n,
      [&](int i) {
        auto image = ReadImage((*entries)[i].image, read);
        if (image.ok()) images[i] = std::move(*image);
        else errors[i] = image.status().message();
        const int done = ++decoded;
        std::lock_guard<std::mutex> lock(bar_mutex);
        bar.Update(done, n + 1, (*entries)[i].image.filename().string());
      },
      args.threads);
  const double decode_seconds = SecondsSince(decode_start);
  for (int i = 0; i < n; ++i)
    if (!errors[i].empty()) return Fail(verb, errors[i]);
  for (int i = 1; i < n; ++i) {
    if (images[i].width() != images[0].width() || images[i].height() != images[0].height())
      return Fail(verb, "images differ in size: " + (*entries)[0].image.string() + " is " +
                            std::to_string(images[0].width()) + "x" + std::to_string(images[0].height()) +
                            " but " + (*entries)[i].image.string() + " is " + std::to_string(images[i].width()) +
                            "x" + std::to_string(images[i].height()));
    if (images[i].channels() != images[0].channels())
      return Fail(verb, "images differ in channel count: " + (*entries)[0].image.string() + " and " +
                            (*entries)[i].image.string());
  }

  PtmFitReport report;
  const auto fit_start = std::chrono::steady_clock::now();
  auto ptm = FitPtm(images, lights, fit, &report);
  const double fit_seconds = SecondsSince(fit_start);
  if (!ptm.ok()) return Fail(verb, ptm.status().message());
  images.clear();
  images.shrink_to_fit();
  bar.Update(n + 1, n + 1, "fit");

  PtmNormalsAlbedo maps;
  if (!args.normals.empty() || !args.albedo.empty()) {
    maps = PtmNormalsAndAlbedo(*ptm, args.threads);
    // Normals map [-1, 1] to [0, 1] as normal maps do.
    for (size_t k = 0; k < maps.normals.size(); ++k) maps.normals.data()[k] = 0.5f * (maps.normals.data()[k] + 1.f);
  }

  // Write: the .ptm, then the optional maps, then the report (each file atomically).
  const auto write_start = std::chrono::steady_clock::now();
  PtmQuantization quantization;
  if (Status s = WritePtmFile(out, *ptm, {}, &quantization); !s.ok()) return Fail(verb, s.message());
  if (!args.normals.empty())
    if (Status s = WriteImage(args.normals, maps.normals, StoredValueOptions(args.normals)); !s.ok())
      return Fail(verb, s.message());
  if (!args.albedo.empty())
    if (Status s = WriteImage(args.albedo, maps.albedo, StoredValueOptions(args.albedo)); !s.ok())
      return Fail(verb, s.message());
  const double write_seconds = SecondsSince(write_start);
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
              {"rms_residual", report.rms_residual},
              {"units", args.linearize ? "linear" : "stored values (as read, not linearised)"}};
  j["quantization"] = {{"scale", quantization.scale}, {"bias", quantization.bias}};
  j["timing"] = {{"decode_seconds", decode_seconds},
                 {"fit_seconds", fit_seconds},
                 {"fit_seconds_core", report.fit_seconds},
                 {"write_seconds", write_seconds},
                 {"total_seconds", total_seconds},
                 {"decode_share", total_seconds > 0 ? decode_seconds / total_seconds : 0.0}};
  j["inputs"] = Json::array();
  for (const LpEntry& e : *entries) j["inputs"].push_back({{"image", e.image.string()}, {"light", ToJson(e.light_dir)}});
  if (Status s = WriteJsonFile(json_path, j); !s.ok()) return Fail(verb, s.message());

  std::printf("%s: %s %dx%d from %d lights, rms residual %.5f; decode %.3f s, fit %.3f s, total %.3f s\n",
              out.string().c_str(), PtmFormatToString(fit.format).c_str(), report.width, report.height,
              report.num_lights, report.rms_residual, decode_seconds, fit_seconds, total_seconds);
  return kExitOk;
}

}  // namespace

Command FitPtmCommand() {
  auto args = std::make_shared<FitPtmArgs>();
  Command c;
  c.name = "fit-ptm";
  c.setup = [args](CLI::App& app) {
    CLI::App* sub = app.add_subcommand(
        "fit-ptm", "Fit a polynomial texture map to an RTI capture (.lp light file + photos); writes .ptm and .json");
    sub->add_option("--lp", args->lp, "RTI light-position file (first line: count; then 'image x y z')")
        ->required();
    sub->add_option("--out", args->out, "Output .ptm (PTM_1.2); the report goes beside it as .json")->required();
    sub->add_option("--format", args->format, "lrgb: luminance polynomial times colour; rgb: one polynomial per channel")
        ->capture_default_str();
    sub->add_option("--normals", args->normals, "Also write surface normals (n+1)/2 to this image (16-bit PNG/TIFF)");
    sub->add_option("--albedo", args->albedo, "Also write the albedo estimate to this image (16-bit PNG/TIFF)");
    sub->add_flag("--linearize", args->linearize,
                  "Decode 8-bit photos from sRGB to linear before fitting (default: fit the stored values, as RTI "
                  "tools and viewers expect)");
    sub->add_option("--threads", args->threads, "Threads (-1: all cores)")->capture_default_str();
    sub->add_flag("--no-progress", args->no_progress, "Do not draw a progress bar");
  };
  c.run = [args]() { return Run(*args); };
  return c;
}

}  // namespace mesocap::app

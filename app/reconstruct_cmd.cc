// mesocap reconstruct: the full BTF from a session's measured slices (Ngan & Durand 2006).
// Reads SESSION/slices/index.json (or --slices INDEX), reconstructs the requested direction
// pairs (default: the Bonn 81 x 81 grid) and writes one OpenEXR slice per pair plus an index.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>


#include "app/commands.h"
#include "core/directions.h"
#include "core/atomic_file.h"
#include "core/image_io.h"
#include "core/parallel.h"
#include "core/provenance.h"
#include "core/session.h"
#include "reconstruct/slice_set.h"

namespace mesocap::app {
namespace {

struct ReconstructArgs {
  std::filesystem::path session, index, out;
  SliceSetOptions options;
  std::vector<std::string> pairs;  // "theta_i,phi_i,theta_o,phi_o"
  bool pixel_only = false;
  bool no_progress = false;
};

bool ParsePair(const std::string& text, std::array<double, 4>* pair) {
  std::stringstream s(text);
  char comma;
  s >> (*pair)[0] >> comma >> (*pair)[1] >> comma >> (*pair)[2] >> comma >> (*pair)[3];
  return !s.fail() && (*pair)[0] >= 0 && (*pair)[0] < 90 && (*pair)[2] >= 0 && (*pair)[2] < 90;
}

int Run(ReconstructArgs& a) {
  const std::filesystem::path index = a.index.empty() ? a.session / "slices" / "index.json" : a.index;
  if (!std::filesystem::exists(index))
    return Fail("reconstruct", index.string() + " not found: run `mesocap calibrate` first or pass --slices");
  std::vector<std::array<double, 4>> pairs;
  for (const std::string& text : a.pairs) {
    std::array<double, 4> p;
    if (!ParsePair(text, &p)) return Fail("reconstruct", "--pair '" + text + "' is not theta_i,phi_i,theta_o,phi_o (degrees, theta < 90)", kExitUsage);
    pairs.push_back(p);
  }
  if (pairs.empty())
    for (const auto& view : BonnDirections())
      for (const auto& light : BonnDirections()) {
        const Eigen::Vector2d i = AnglesDegFromDirection(light), o = AnglesDegFromDirection(view);
        pairs.push_back({i.x(), i.y(), o.x(), o.y()});
      }
  if (!IsMissingOrEmptyDir(a.out)) return Fail("reconstruct", a.out.string() + ": exists and is not empty", kExitUsage);
  a.options.btf.match_subbands = !a.pixel_only;
  if (!a.options.Check()) return Fail("reconstruct", "--size must be a power of two", kExitUsage);

  SliceSetReport loaded;
  ProgressBar load_bar("statistics", !a.no_progress);
  auto btf = LoadStatisticalBtf(index, a.options, &loaded, load_bar.AsCallback());
  for (const std::string& s : loaded.skipped) std::fprintf(stderr, "mesocap reconstruct: skipped %s\n", s.c_str());
  if (!btf.ok()) return Fail("reconstruct", btf.status().message());

  // Everything goes to a staging folder published at the end: an interrupted or failed run
  // leaves nothing under the output's name.
  std::filesystem::path out = std::filesystem::absolute(a.out);
  if (out.filename().empty()) out = out.parent_path();  // "out/" names "out"
  const std::filesystem::path staging = StagingFolderFor(out);
  std::error_code ec;
  std::filesystem::remove_all(staging, ec);
  std::filesystem::create_directories(staging / "slices", ec);
  if (ec) return Fail("reconstruct", staging.string() + ": cannot create: " + ec.message());
  auto fail = [&](const std::string& message, int code = kExitFailure) {
    std::filesystem::remove_all(staging, ec);
    return Fail("reconstruct", message, code);
  };
  std::vector<Json> entries(pairs.size());
  std::vector<std::string> errors(pairs.size());
  ProgressBar bar("reconstruct", !a.no_progress);
  const auto start = std::chrono::steady_clock::now();
  std::atomic<int> done = 0;
  std::atomic<bool> cancelled = false;
  ParallelFor(0, int(pairs.size()), [&](int k) {
    if (cancelled) return;
    const auto& p = pairs[k];
    const Image slice = btf->Reconstruct(DirectionFromAnglesDeg(p[0], p[1]), DirectionFromAnglesDeg(p[2], p[3]));
    char name[96];
    std::snprintf(name, sizeof name, "slices/ti%04.1f_pi%05.1f_to%04.1f_po%05.1f.exr", p[0], p[1], p[2], p[3]);
    ImageWriteOptions w;
    w.format = PixelFormat::kHalf;
    w.attributes["mesocap:theta_i_deg"] = float(p[0]);
    w.attributes["mesocap:phi_i_deg"] = float(p[1]);
    w.attributes["mesocap:theta_o_deg"] = float(p[2]);
    w.attributes["mesocap:phi_o_deg"] = float(p[3]);
    w.attributes["mesocap:quantity"] = std::string("BTF: radiance per unit perpendicular irradiance (includes cos theta_i)");
    w.attributes["mesocap:method"] = std::string(a.pixel_only ? "statistical (pixel histogram)" : "statistical (Ngan & Durand 2006)");
    if (Status st = WriteImage(staging / name, slice, w); !st.ok()) errors[k] = st.message();
    entries[k] = {{"file", name}, {"theta_i_deg", p[0]}, {"phi_i_deg", p[1]}, {"theta_o_deg", p[2]}, {"phi_o_deg", p[3]}};
    if (!bar.Update(++done, int(pairs.size()), name)) cancelled = true;
  }, a.options.btf.num_threads);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (const std::string& e : errors)
    if (!e.empty()) return fail(e);
  if (cancelled) return fail("cancelled", kExitCancelled);

  Json j = {{"format", "mesocap-btf"}, {"width", btf->width()}, {"height", btf->height()},
            {"views_measured", loaded.views}, {"top_board", loaded.top_board}, {"top_lights", loaded.top_lights},
            {"slices_used", loaded.slices_used}, {"skipped", loaded.skipped},
            {"seconds_statistics", loaded.seconds}, {"seconds_reconstruct", seconds},
            {"ms_per_slice", 1000 * seconds / pairs.size()}, {"slices", entries}};
  j["provenance"] = MakeProvenance({{"index", index.string()}, {"size", a.options.size}, {"pixel_only", a.pixel_only}});
  if (Status st = WriteJsonFile(staging / "index.json", j); !st.ok()) return fail(st.message());
  if (Status st = PublishStagingFolder(staging, out); !st.ok()) return fail(st.message());
  std::printf("reconstructed %zu slices (%dx%d) from %d measured slices in %d views: statistics %.1f s, reconstruction "
              "%.1f s (%.1f ms per slice, written) -> %s\n",
              pairs.size(), btf->width(), btf->height(), loaded.slices_used, loaded.views, loaded.seconds, seconds,
              1000 * seconds / pairs.size(), out.string().c_str());
  return kExitOk;
}

}  // namespace

Command ReconstructCommand() {
  auto args = std::make_shared<ReconstructArgs>();
  Command c;
  c.name = "reconstruct";
  c.setup = [args](CLI::App& app) {
    CLI::App* sub = app.add_subcommand("reconstruct", "Reconstruct a full BTF from a session's measured slices (statistical, Ngan & Durand)");
    sub->add_option("session", args->session, "Session folder (reads SESSION/slices/index.json)");
    sub->add_option("--slices", args->index, "A slice index.json instead of the session's");
    sub->add_option("--out", args->out, "Output folder (must not exist or be empty)")->required();
    sub->add_option("--pair", args->pairs, "theta_i,phi_i,theta_o,phi_o in degrees (repeatable; default: the Bonn 81x81 grid)");
    sub->add_option("--size", args->options.size, "Resample slices to this many texels a side (power of two; 0 keeps theirs)")
        ->capture_default_str();
    sub->add_flag("--pixel-only", args->pixel_only, "Match the pixel histogram only (no subbands)");
    sub->add_option("--threads", args->options.btf.num_threads, "Threads (-1: all cores)")->capture_default_str();
    sub->add_flag("--no-progress", args->no_progress, "Do not draw a progress bar");
  };
  c.run = [args]() {
    if (args->session.empty() && args->index.empty()) return Fail("reconstruct", "give a SESSION or --slices INDEX", kExitUsage);
    return Run(*args);
  };
  return c;
}

}  // namespace mesocap::app

// mesocap reconstruct: the full BTF from a session's measured slices (Ngan & Durand 2006).
// Reads SESSION/slices/index.json (or --slices INDEX), reconstructs the requested direction
// pairs (default: the Bonn 81 x 81 grid) and writes one OpenEXR slice per pair plus an index.
#include "app/reconstruct_args.h"

#include <atomic>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>

#include "app/btf_folder.h"
#include "app/btf_method_args.h"
#include "app/commands.h"
#include "core/atomic_file.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "core/parallel.h"
#include "core/provenance.h"
#include "core/session.h"
#include "core/session_layout.h"
#include "core/text_format.h"
#include "reconstruct/slice_set.h"

namespace mesocap::app {
namespace {

// "theta_i,phi_i,theta_o,phi_o": exactly four numbers separated by commas, nothing else; theta in
// [0, 90), phi normalised into [0, 360). An empty string means the text was valid.
std::string ParsePair(const std::string& text, std::array<double, 4>* pair) {
  const std::string usage = "--pair '" + text + "' is not theta_i,phi_i,theta_o,phi_o (degrees, theta in [0, 90))";
  size_t start = 0;
  for (int k = 0; k < 4; ++k) {
    const size_t end = k < 3 ? text.find(',', start) : text.size();
    if (end == std::string::npos) return usage;
    const std::string field = text.substr(start, end - start);
    char* stop = nullptr;
    errno = 0;
    const double value = field.empty() || std::isspace(static_cast<unsigned char>(field[0]))
                             ? NAN : std::strtod(field.c_str(), &stop);
    if (errno != 0 || !std::isfinite(value) || stop != field.c_str() + field.size()) return usage;
    (*pair)[k] = value;
    start = end + 1;
  }
  for (int k : {0, 2})
    if (!((*pair)[k] >= 0 && (*pair)[k] < 90)) return usage;
  for (int k : {1, 3}) {
    (*pair)[k] = std::fmod((*pair)[k], 360.0);
    if ((*pair)[k] < 0) (*pair)[k] += 360.0;
    if ((*pair)[k] >= 359.95) (*pair)[k] = 0.0;  // would print as 360.0: the same azimuth as 0
  }
  return "";
}

int ReconstructToFolder(ReconstructArgs& a) {
  const std::filesystem::path index = a.index.empty() ? SessionLayout(a.session).slices().index() : a.index;
  if (!std::filesystem::exists(index))
    return Fail("reconstruct", index.string() + " not found: run `mesocap calibrate` first or pass --slices");
  std::vector<DirectionPair> pairs;
  std::map<std::string, std::string> named;  // slice file -> the --pair that asked for it
  for (const std::string& text : a.pairs) {
    std::array<double, 4> p;
    if (std::string why = ParsePair(text, &p); !why.empty()) return Fail("reconstruct", why, kExitUsage);
    const auto [it, added] = named.emplace(BtfSliceName(p), text);
    if (!added)
      return Fail("reconstruct", "--pair '" + text + "' and --pair '" + it->second + "' both name " + it->first +
                                     " (angles are kept to 0.1 deg): give distinct directions", kExitUsage);
    pairs.push_back(p);
  }
  if (pairs.empty()) pairs = GridPairs(a.grid);
  if (pairs.empty()) return Fail("reconstruct", "--grid must be bonn or coarse, not '" + a.grid + "'", kExitUsage);
  if (!IsMissingOrEmptyDir(a.out)) return Fail("reconstruct", a.out.string() + ": exists and is not empty", kExitUsage);
  a.options.btf.match_subbands = !a.pixel_only;
  a.method.ApplyTo(&a.options);  // the colour space was checked by CLI11
  if (!a.options.Check()) return Fail("reconstruct", "--size must be a power of two", kExitUsage);

  SliceSetReport loaded;
  ProgressBar load_bar("statistics", !a.no_progress);
  auto btf = LoadStatisticalBtf(index, a.options, &loaded, load_bar.AsCallback());
  for (const std::string& s : loaded.skipped) std::fprintf(stderr, "mesocap reconstruct: skipped %s\n", s.c_str());
  for (const std::string& w : loaded.warnings) std::fprintf(stderr, "mesocap reconstruct: warning: %s\n", w.c_str());
  if (!btf.ok()) return Fail("reconstruct", btf.status());

  // Everything goes to a staging folder published at the end: an interrupted or failed run
  // (a worker's exception included) leaves nothing under the output's name.
  auto staging = StagingFolder::Begin(a.out);
  if (!staging.ok()) return Fail("reconstruct", staging.status());
  const auto fail = [](const std::string& message, int code = kExitFailure) { return Fail("reconstruct", message, code); };
  ProgressBar bar("reconstruct", !a.no_progress);
  Json provenance = a.method.ToJson();
  provenance.update({{"index", index.string()}, {"size", a.options.size}, {"pixel_only", a.pixel_only}});
  auto written = WriteReconstructedBtf(*btf, loaded, pairs, a.pixel_only, a.options.btf.num_threads, staging->path(),
                                       provenance, bar.AsCallback());
  if (!written.ok()) return Fail("reconstruct", written.status());
  const double seconds = written->seconds;
  if (Status st = staging->Publish(); !st.ok()) return fail(st.message());
  std::printf("reconstructed %zu slices (%dx%d) from %d measured slices in %d views%s: statistics %.1f s, reconstruction "
              "%.1f s (%.1f ms per slice, written) -> %s\n",
              pairs.size(), btf->width(), btf->height(), loaded.slices_used, loaded.views,
              loaded.chroma_from_top ? " (colour from the top view)" : "", loaded.seconds, seconds,
              1000 * seconds / pairs.size(), staging->out().string().c_str());
  return kExitOk;
}

}  // namespace

int RunReconstruct(ReconstructArgs& a) {
  if (a.session.empty() && a.index.empty()) return Fail("reconstruct", "give a SESSION or --slices INDEX", kExitUsage);
  if (!a.session.empty())
    if (std::string named = a.method.TakeSessionMirrorImages(a.session); !named.empty())
      std::fprintf(stderr, "mesocap reconstruct: images the capture was guided by: %s (--mirror-images overrides)\n",
                   named.c_str());
  return ReconstructToFolder(a);
}

}  // namespace mesocap::app

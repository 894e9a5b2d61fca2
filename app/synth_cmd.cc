// mesocap synth, synth-apply, paint: enlarge a material (synth/). Each finds a texture-coordinate
// map on the exemplar's compact features and applies it to every slice (or the image, or the PTM).
#include "app/synth_args.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "app/commands.h"
#include "app/synth_output.h"
#include "app/synth_run.h"
#include "core/image_io.h"
#include "core/json.h"
#include "core/progress.h"
#include "core/session.h"
#include "synth/exemplar.h"
#include "synth/quilt.h"
#include "synth/roller.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;

// Checks shared by the three commands; returns a non-zero exit code on a bad option.
int CheckCommon(const std::string& verb, SynthArgs& a, int* width, int* height) {
  if (!a.out.empty() && !IsMissingOrEmptyDir(a.out)) return Fail(verb, a.out.string() + ": exists and is not empty", kExitUsage);
  if (width && !ParseSize(a.size, width, height))
    return Fail(verb, "--size '" + a.size + "' is not WxH (1..32768 each)", kExitUsage);
  a.exemplar.num_threads = a.threads;
  return 0;
}

StatusOr<Exemplar> Load(const SynthArgs& a, const std::string& verb) {
  ProgressBar bar("features", !a.no_progress);
  return LoadExemplar(a.input, a.exemplar, bar.AsCallback());
}

int Finish(const std::string& verb, const SynthMap& map, const Exemplar& e, const SynthArgs& a, Json report,
           std::function<Status(const fs::path&)> write_extra = nullptr) {
  SynthOutputRequest request;
  request.write_extra = std::move(write_extra);
  request.out = a.out;
  request.report = std::move(report);
  request.num_threads = a.threads;
  if (e.kind == ExemplarKind::kBtf && !ParseSliceList(a.slices, int(e.slices.size()), &request.slices))
    return Fail(verb, "--slices '" + a.slices + "' is not 'all' or indices 0.." + std::to_string(e.slices.size() - 1), kExitUsage);
  ProgressBar bar("writing", !a.no_progress);
  if (Status st = WriteSynthesisOutputs(map, e, request, bar.AsCallback()); !st.ok()) return Fail(verb, st);
  std::printf("%s: %s %dx%d from %s (%s, %dx%d) -> %s\n", verb.c_str(), map.method.c_str(), map.width, map.height,
              a.input.string().c_str(), ExemplarKindToString(e.kind).c_str(), e.width, e.height, a.out.string().c_str());
  return kExitOk;
}

}  // namespace

int RunSynth(SynthArgs& a) {
  const std::string verb = "synth";
  if (!IsSynthMethod(a.method))
    return Fail(verb, "unknown method '" + a.method + "' (roller, quilt, ptm-block, texton)", kExitUsage);
  int width = 0, height = 0;
  if (int code = CheckCommon(verb, a, &width, &height)) return code;
  auto e = Load(a, verb);
  if (!e.ok()) return Fail(verb, e.status());
  SynthMethodOptions method;
  method.method = a.method;
  method.width = width, method.height = height, method.seed = a.seed, method.num_threads = a.threads;
  method.roller = a.roller;
  method.quilt = a.quilt;
  method.block = a.block;
  method.block.search = a.brute_force ? BlockSearch::kBruteForce : BlockSearch::kRejection;
  if (a.block_basis != "principal" && a.block_basis != "walsh")
    return Fail(verb, "--bound-basis must be principal or walsh, not '" + a.block_basis + "'", kExitUsage);
  method.block.basis = a.block_basis == "walsh" ? BlockBasis::kWalshHadamard : BlockBasis::kPrincipal;
  method.texton_analysis = a.texton_analysis;
  method.texton = a.texton;
  method.texton.search = a.brute_force ? TextonSearch::kFull : TextonSearch::kCoherence;
  method.textons = a.analysis;
  if (a.method == "texton") {
    if (Status st = method.texton_analysis.Check(); !st.ok()) return Fail(verb, st.message(), kExitUsage);
    if (Status st = method.texton.Check(); !st.ok()) return Fail(verb, st.message(), kExitUsage);
  }
  method.svd_components = a.exemplar.svd_components;
  Json report;
  std::string note;
  ProgressBar bar(a.method == "quilt" ? "quilting" : a.method, !a.no_progress);
  TextonAnalysis textons;
  auto map = RunSynthesisMethod(*e, method, &report, &note, bar.AsCallback(), &textons);
  if (!map.ok())
    return Fail(verb, map.status().WithContext(a.input.string() + ": "));
  if (!note.empty()) std::fprintf(stderr, "mesocap synth: %s: %s\n", a.input.string().c_str(), note.c_str());
  // A texton analysis is kept beside the map, so a later run (or a surface) reuses it with --analysis.
  return Finish(verb, *map, *e, a, report, TextonAnalysisWriter(textons));
}

int RunSynthApply(SynthArgs& a) {
  const std::string verb = "synth-apply";
  if (int code = CheckCommon(verb, a, nullptr, nullptr)) return code;
  auto map = ReadSynthMap(a.map);
  if (!map.ok()) return Fail(verb, map.status());
  a.exemplar.svd_components = 1;  // the map is given: features only feed the report
  auto e = Load(a, verb);
  if (!e.ok()) return Fail(verb, e.status());
  if (e->width != map->sample_width || e->height != map->sample_height)
    return Fail(verb, a.map.string() + ": points into a " + std::to_string(map->sample_width) + "x" +
                          std::to_string(map->sample_height) + " sample; " + a.input.string() + " is " +
                          std::to_string(e->width) + "x" + std::to_string(e->height));
  return Finish(verb, *map, *e, a, {{"method", map->method}, {"map", a.map.string()}});
}

int RunPaint(SynthArgs& a) {
  const std::string verb = "paint";
  int width = 0, height = 0;
  if (int code = CheckCommon(verb, a, &width, &height)) return code;
  auto feature = ReadMask(a.feature_mask);
  if (!feature.ok()) return Fail(verb, feature.status());
  auto target = ReadMask(a.target_mask);
  if (!target.ok()) return Fail(verb, target.status());
  auto e = Load(a, verb);
  if (!e.ok()) return Fail(verb, e.status());
  if (feature->width() != e->width || feature->height() != e->height)
    return Fail(verb, a.feature_mask.string() + ": " + std::to_string(feature->width()) + "x" + std::to_string(feature->height()) +
                          ", the sample is " + std::to_string(e->width) + "x" + std::to_string(e->height));
  if (target->width() != width || target->height() != height)
    return Fail(verb, a.target_mask.string() + ": " + std::to_string(target->width()) + "x" + std::to_string(target->height()) +
                          ", --size is " + std::to_string(width) + "x" + std::to_string(height));
  QuiltOptions o = a.quilt;
  o.width = width, o.height = height, o.seed = a.seed, o.num_threads = a.threads;
  QuiltReport r;
  ProgressBar bar("painting", !a.no_progress);
  auto map = PaintSynthesis(e->features, *feature, *target, o, a.paint, &r, bar.AsCallback());
  if (!map.ok()) return Fail(verb, map.status().WithContext(a.input.string() + ": "));
  Json report = {{"method", "paint"}};
  report["parameters"] = {{"transition_width", a.paint.transition_width}, {"match_weight", a.paint.match_weight},
                          {"data_weight", a.paint.data_weight}, {"verbatim", a.paint.verbatim}, {"seed", a.seed},
                          {"width", width}, {"height", height}, {"feature_mask", a.feature_mask.string()},
                          {"target_mask", a.target_mask.string()}};
  report["patches"] = r.patches;
  report["repair_patches"] = r.repair_patches;
  report["seconds_synthesis"] = r.seconds;
  return Finish(verb, *map, *e, a, report);
}
}  // namespace mesocap::app

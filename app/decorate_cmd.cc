// mesocap decorate: a mesh dressed in the material (app/decorate_run.h), written whole or not at all.
#include <cstdio>

#include "app/commands.h"
#include "app/decorate_args.h"
#include "app/decorate_run.h"
#include "app/material_maps.h"
#include "app/synth_output.h"
#include "app/synth_stage.h"
#include "core/atomic_file.h"
#include "core/progress.h"
#include "core/session.h"

namespace mesocap::app {
namespace {
constexpr const char* kVerb = "decorate";
constexpr int kMaxBtfSlices = 289;  // as process's stages take of the 6561-slice grid
}  // namespace

int RunDecorate(DecorateArgs& a) {
  if (!IsMissingOrEmptyDir(a.out)) return Fail(kVerb, a.out.string() + ": exists and is not empty", kExitUsage);
  DecorateRequest request;
  if (!ParseSize(a.preview_size, &request.preview_width, &request.preview_height))
    return Fail(kVerb, "--preview-size '" + a.preview_size + "' is not WxH", kExitUsage);
  request.mesh = a.mesh, request.field = a.field;
  request.method = a.method;
  request.texton = a.texton, request.texton_analysis = a.texton_analysis;
  request.quilt = a.quilt, request.quilt.texel_size = a.texton.texel_size, request.quilt.seed = a.seed;
  request.quilt.num_threads = a.threads;
  request.texton.seed = a.seed, request.texton.num_threads = a.threads;
  request.texton_analysis.num_threads = a.threads, request.texton_analysis.seed = a.seed;
  request.atlas_size = a.atlas_size, request.threads = a.threads, request.progress = !a.no_progress;
  if (Status st = request.texton.Check(); !st.ok()) return Fail(kVerb, st.message(), kExitUsage);

  ExemplarOptions exemplar_options;
  exemplar_options.features = a.method == "quilt";  // quilting matches features; textons analyse the slices
  exemplar_options.board = a.board, exemplar_options.num_threads = a.threads;
  auto exemplar = LoadExemplar(a.input, exemplar_options);
  if (!exemplar.ok()) return Fail(kVerb, exemplar.status());
  Exemplar shown = *exemplar;  // a large BTF: its coarse-grid slices (analysis and previews read each one)
  if (shown.kind == ExemplarKind::kBtf && int(shown.slices.size()) > kMaxBtfSlices) {
    shown.slices.clear();
    for (int k : StageSlices(*exemplar, kMaxBtfSlices)) shown.slices.push_back(exemplar->slices[k]);
  }
  StatusOr<GgxMaterialMaps> material = Status::Error("");
  {
    ProgressBar bar("material", !a.no_progress && exemplar->kind == ExemplarKind::kBtf);
    material = ExemplarMaterialMaps(*exemplar, a.board, a.threads, bar.AsCallback());
  }
  if (!material.ok()) return Fail(kVerb, material.status());
  auto staging = StagingFolder::Begin(a.out);
  if (!staging.ok()) return Fail(kVerb, staging.status());
  auto result = DecorateInto(DecorateFolder{staging->path()}, request, shown, *material);
  if (!result.ok()) return Fail(kVerb, result.status());
  for (const std::string& line : result->repairs) std::fprintf(stderr, "decorate: %s: repaired: %s\n", a.mesh.string().c_str(), line.c_str());
  if (Status st = staging->Publish(); !st.ok()) return Fail(kVerb, st);
  std::printf("decorate: %s dressed in %s (%s, %dx%d) -> %s\n", result->brief.c_str(), a.input.string().c_str(),
              ExemplarKindToString(exemplar->kind).c_str(), exemplar->width, exemplar->height, a.out.string().c_str());
  return kExitOk;
}

}  // namespace mesocap::app

// A diagnostic (issue 12): a copy of a calibrated virtual session whose slices are replaced by true
// slices at the same lights and views, so `mesocap evaluate --session COPY` scores what the
// session's lights give on evaluate's own path (its pairs, its truth, its method options, which
// follow the slices' index as the original's do), against what its calibrated slices give.
//
// Usage: bench_true_session_slices SESSION COPY [--top-region 1]
// Every slice listed in SESSION/slices/index.json is rendered with a directional light from its
// (theta_i, phi_i), seen from its (theta_o, phi_o), on its board's own part of the material (the
// rig's material_offset_m; with --top-region 1, the top board's part, as the held-out truth is)
// at the slice's own size and the samples per texel the rig renders the patch with. The index,
// truth.json and the session's other files are copied as they are, so evaluate also undoes the
// session's capture blur (--capture-blur-px, from each slice's texel_px) on these true slices,
// which have none: `evaluate --capture-blur-px 0` scores them as true slices.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "capture/btf_render.h"
#include "capture/rig_material.h"
#include "capture/rig_render.h"
#include "capture/rig_scene.h"
#include "core/image_io.h"
#include "core/json.h"
#include "core/parallel.h"
#include "core/slice_index.h"
#include "reconstruct/slice_set.h"

namespace mesocap {
namespace {

namespace fs = std::filesystem;

int Run(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: bench_true_session_slices SESSION COPY [--top-region 1]\n");
    return 2;
  }
  const fs::path session = argv[1], copy = argv[2];
  const bool top_region = argc >= 5 && std::string(argv[3]) == "--top-region" && std::string(argv[4]) == "1";
  const fs::path index_json = session / "slices" / "index.json";
  auto truth_json = ReadJsonFile(session / "truth.json");
  if (!truth_json.ok()) return std::fprintf(stderr, "%s\n", truth_json.status().message().c_str()), 1;
  auto scene = TruthFromJson(*truth_json);
  if (!scene.ok()) return std::fprintf(stderr, "%s\n", scene.status().message().c_str()), 1;
  auto material = Material::Create(scene->options.material);
  if (!material.ok()) return std::fprintf(stderr, "%s\n", material.status().message().c_str()), 1;
  auto index = ReadSliceIndex(index_json);
  if (!index.ok()) return std::fprintf(stderr, "%s\n", index.status().message().c_str()), 1;
  // With --top-region, the top board as evaluate picks it (the most head-on with lights enough);
  // only then are its slices read.
  SliceSetReport top;
  if (top_region)
    if (auto view = LoadTopView(index_json, SliceSetOptions(), &top); !view.ok())
      return std::fprintf(stderr, "%s\n", view.status().message().c_str()), 1;
  fs::create_directories(copy / "slices");
  for (const auto& entry : fs::directory_iterator(session))
    if (entry.is_regular_file()) fs::copy_file(entry.path(), copy / entry.path().filename(), fs::copy_options::overwrite_existing);
  for (const auto& entry : fs::directory_iterator(session / "slices"))
    if (entry.path().extension() == ".lp" || entry.path().filename() == "index.json")
      fs::copy_file(entry.path(), copy / "slices" / entry.path().filename(), fs::copy_options::overwrite_existing);

  const auto board_of = [&](int id) -> const RigBoard* {
    for (const RigBoard& b : scene->boards)
      if (b.id == id) return &b;
    return nullptr;
  };
  const std::vector<SliceIndexEntry>& slices = index->slices;
  std::vector<std::string> errors(slices.size());
  ParallelFor(0, int(slices.size()), [&](int s) {
    const SliceIndexEntry& slice = slices[size_t(s)];
    const RigBoard* board = board_of(top_region ? top.top_board : slice.board);
    auto info = ReadImageInfo(slice.file);  // rendered at the calibrated slice's own size
    if (!board || !info.ok()) {
      errors[size_t(s)] = slice.file.string() + (board ? ": " + info.status().message() : ": its board is not in truth.json");
      return;
    }
    TrueBtfRequest request = TrueBtfRequestFor(slice.light, slice.view, info->width, RigTruthSamplesPerAxis(info->width));
    request.patch_m = board->patch_m;
    request.offset_m = board->material_offset_m;
    const fs::path file = copy / "slices" / fs::relative(slice.file, session / "slices");
    fs::create_directories(file.parent_path());
    if (Status st = WriteImage(file, RenderTrueBtfSlice(*material, request, 1), {.format = PixelFormat::kHalf}); !st.ok())
      errors[size_t(s)] = st.message();
  });
  int failures = 0;
  for (const std::string& error : errors)
    if (!error.empty()) ++failures, std::fprintf(stderr, "%s\n", error.c_str());
  std::printf("%zu true slices written to %s (%s region)%s\n", slices.size(), (copy / "slices").c_str(),
              top_region ? "the top board's" : "each board's own",
              failures ? (", " + std::to_string(failures) + " failed").c_str() : "");
  return failures ? 1 : 0;
}

}  // namespace
}  // namespace mesocap

int main(int argc, char** argv) { return mesocap::Run(argc, argv); }

// A diagnostic (issue 12): a copy of a calibrated virtual session whose slices are replaced by true
// slices at the same lights and views, so `mesocap evaluate --session COPY` scores what the
// session's lights give on evaluate's own path (its pairs, its truth, its method options, which
// follow the slices' index as the original's do), against what its calibrated slices give.
//
// Usage: bench_true_session_slices SESSION COPY [--top-region 1]
// Every slice listed in SESSION/slices/index.json is rendered with a directional light from its
// (theta_i, phi_i), seen from its (theta_o, phi_o), on its board's own part of the material (the
// rig's material_offset_m; with --top-region 1, the top board's part, as the held-out truth is)
// at the samples per texel the rig renders the patch with. The index, truth.json and the
// session's other files are copied as they are.
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
  auto truth_json = ReadJsonFile(session / "truth.json");
  auto index = ReadJsonFile(session / "slices" / "index.json");
  if (!truth_json.ok() || !index.ok()) {
    std::fprintf(stderr, "%s: needs truth.json and slices/index.json\n", session.c_str());
    return 1;
  }
  auto scene = TruthFromJson(*truth_json);
  if (!scene.ok()) return std::fprintf(stderr, "%s\n", scene.status().message().c_str()), 1;
  auto material = Material::Create(scene->options.material);
  if (!material.ok()) return std::fprintf(stderr, "%s\n", material.status().message().c_str()), 1;
  fs::create_directories(copy / "slices");
  for (const auto& entry : fs::directory_iterator(session))
    if (entry.is_regular_file()) fs::copy_file(entry.path(), copy / entry.path().filename(), fs::copy_options::overwrite_existing);
  fs::copy_file(session / "slices" / "index.json", copy / "slices" / "index.json", fs::copy_options::overwrite_existing);
  for (const auto& entry : fs::directory_iterator(session / "slices"))
    if (entry.path().extension() == ".lp")
      fs::copy_file(entry.path(), copy / "slices" / entry.path().filename(), fs::copy_options::overwrite_existing);

  const int size = index->at("size").get<int>();
  const Json& slices = index->at("slices");
  const int top_board = [&] {
    int best = 0;
    double least = 1e9;
    for (const RigBoard& b : scene->boards)
      if (b.view_incidence_deg < least) least = b.view_incidence_deg, best = b.id;
    return best;
  }();
  const auto board_of = [&](int id) -> const RigBoard& {
    for (const RigBoard& b : scene->boards)
      if (b.id == id) return b;
    return scene->boards.front();
  };
  std::vector<int> failed(slices.size(), 0);
  ParallelFor(0, int(slices.size()), [&](int s) {
    const Json& slice = slices[size_t(s)];
    const RigBoard& board = board_of(top_region ? top_board : slice.at("board").get<int>());
    TrueBtfRequest request;
    request.theta_i_deg = slice.at("theta_i_deg").get<double>();
    request.phi_i_deg = slice.at("phi_i_deg").get<double>();
    request.theta_o_deg = slice.at("theta_o_deg").get<double>();
    request.phi_o_deg = slice.at("phi_o_deg").get<double>();
    request.size = size;
    request.samples_per_axis = RigTruthSamplesPerAxis(size);
    request.patch_m = board.patch_m;
    request.offset_m = board.material_offset_m;
    const fs::path file = copy / "slices" / slice.at("file").get<std::string>();
    fs::create_directories(file.parent_path());
    const Image rendered = RenderTrueBtfSlice(*material, request, 1);
    failed[size_t(s)] = !WriteImage(file, rendered, {.format = PixelFormat::kHalf}).ok();
  });
  int failures = 0;
  for (int f : failed) failures += f;
  std::printf("%zu true slices of %d x %d texels written to %s (%s region)%s\n", slices.size(), size, size,
              (copy / "slices").c_str(), top_region ? "the top board's" : "each board's own",
              failures ? (", " + std::to_string(failures) + " failed").c_str() : "");
  return failures ? 1 : 0;
}

}  // namespace
}  // namespace mesocap

int main(int argc, char** argv) { return mesocap::Run(argc, argv); }

// bench_make_btf_slice_set OUT_DIR [SIZE=256] [MATERIAL=weave]: renders a virtual material's
// true BTF at the rig's 13 views under the Bonn 81 lights and writes it as a measured slice set
// (OUT_DIR/board_BB/light_LL.exr + OUT_DIR/index.json in the format `mesocap calibrate` writes),
// the input of `mesocap reconstruct --slices` for benchmarks.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "capture/btf_render.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "core/json.h"
#include "core/parallel.h"
#include "reconstruct/btf_evaluation.h"

int main(int argc, char** argv) {
  using namespace mesocap;
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_make_btf_slice_set OUT_DIR [SIZE] [MATERIAL]\n");
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  const int size = argc > 2 ? std::atoi(argv[2]) : 256;
  auto material = Material::Create(argc > 3 ? argv[3] : "weave");
  if (!material.ok()) {
    std::fprintf(stderr, "%s\n", material.status().message().c_str());
    return 2;
  }
  const auto views = RigViewDirections(), lights = BonnDirections();
  const int n = int(views.size() * lights.size());
  std::vector<Json> entries(n);
  std::vector<std::string> errors(n);
  ParallelFor(0, n, [&](int k) {
    const int v = k / int(lights.size()), l = k % int(lights.size());
    const Eigen::Vector2d i = AnglesDegFromDirection(lights[l]), o = AnglesDegFromDirection(views[v]);
    const TrueBtfRequest r = TrueBtfRequestFor(lights[l], views[v], size);
    char name[64];
    std::snprintf(name, sizeof name, "board_%02d/light_%02d.exr", v, l);
    std::filesystem::create_directories(dir / std::string(name).substr(0, 8));
    ImageWriteOptions w;
    w.format = PixelFormat::kHalf;
    if (Status st = WriteImage(dir / name, RenderTrueBtfSlice(*material, r, 1), w); !st.ok()) errors[k] = st.message();
    entries[k] = {{"file", name}, {"board", v}, {"theta_i_deg", i.x()}, {"phi_i_deg", i.y()},
                  {"theta_o_deg", o.x()}, {"phi_o_deg", o.y()}};
  });
  for (const auto& e : errors)
    if (!e.empty()) {
      std::fprintf(stderr, "%s\n", e.c_str());
      return 1;
    }
  if (Status st = WriteJsonFile(dir / "index.json", Json{{"format", "mesocap-slices"}, {"size", size}, {"slices", entries}}); !st.ok()) {
    std::fprintf(stderr, "%s\n", st.message().c_str());
    return 1;
  }
  std::printf("%d slices of %dx%d -> %s\n", n, size, size, (dir / "index.json").c_str());
  return 0;
}

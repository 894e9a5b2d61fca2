// How many of a session's top-view lights the mirror symmetry check (CheckMirrorSymmetry) needs
// before it reaches the verdict the whole session gives, and how far an imaged light may lie from
// a measured one: the check as `mesocap capture --guide` runs it while the session grows.
//
//   bench_symmetry_check SESSION/slices/index.json [LIGHTS=12,24,40,70,0] [GAPS=10,20]
//
// Takes the top board's slices in shot order (the first LIGHTS of them; 0: all) as the
// reconstruction loads them (LoadTopView) at 64 texels, and prints per gap which images hold (one
// digit per MirrorImages() entry) and the lights each image was tested on.
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "reconstruct/mirror_symmetry.h"
#include "reconstruct/slice_set.h"
#include "reconstruct/statistical_btf.h"

using namespace mesocap;

namespace {

std::vector<double> Numbers(const std::string& list) {
  std::vector<double> out;
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) out.push_back(std::stod(item));
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SLICES_INDEX_JSON [LIGHTS=12,24,40,70,0] [GAPS=10,20]\n", argv[0]);
    return 2;
  }
  const std::vector<double> counts = Numbers(argc > 2 ? argv[2] : "12,24,40,70,0");
  const std::vector<double> gaps = Numbers(argc > 3 ? argv[3] : "10,20");
  // The top view as the reconstruction loads it (and `mesocap coverage`), at 64 texels; the check
  // reads the first channel, the brightness R + G + B.
  SliceSetOptions options;
  options.size = 64;
  options.remove_chroma_noise = false;
  SliceSetReport report;
  auto top = LoadTopView(argv[1], options, &report);
  if (!top.ok()) {
    std::fprintf(stderr, "%s\n", top.status().message().c_str());
    return 1;
  }
  const StatisticalBtfOptions& btf = options.btf;
  std::printf("%s: top board %d, %zu lights\nlights gap  holds    tested lights per image\n", argv[1], report.top_board,
              top->lights.size());
  for (const double count : counts) {
    MeasuredView first = *top;
    const size_t n = count > 0 && size_t(count) < top->lights.size() ? size_t(count) : top->lights.size();
    first.lights.resize(n);
    first.statistics.resize(n);
    if (!first.mean_rgb.empty()) first.mean_rgb.resize(n);
    for (const double gap : gaps) {
      const MirrorSymmetryCheck check =
          CheckMirrorSymmetry(first, btf.statistics.pyramid.orientations, btf.min_light_separation_deg, gap);
      std::string holds, tested;
      for (size_t k = 0; k < check.holds.size(); ++k)
        holds += check.holds[k] ? '1' : '0', tested += " " + std::to_string(check.lights[k]);
      std::printf("%5zu %4.0f  %s %s\n", n, gap, check.tested ? holds.c_str() : "untested", tested.c_str());
    }
  }
  return 0;
}

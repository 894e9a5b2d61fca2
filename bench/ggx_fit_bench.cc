// Times the GGX fit (export/ggx_fit.h) of a BTF folder and prints its figures as one JSON line.
//   bench_ggx_fit INDEX.json [max_slices]
#include <cstdio>
#include <string>

#include "export/ggx_fit.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_ggx_fit INDEX.json [max_slices]\n");
    return 2;
  }
  mesocap::GgxFitOptions options;
  if (argc > 2) options.max_slices = std::stoi(argv[2]);
  auto maps = mesocap::FitGgxMaterial(argv[1], options);
  if (!maps.ok()) {
    std::fprintf(stderr, "bench_ggx_fit: %s\n", maps.status().message().c_str());
    return 1;
  }
  mesocap::Json j = maps->ToJson();
  j["options"] = options.ToJson();
  std::printf("%s\n", j.dump().c_str());
  return 0;
}

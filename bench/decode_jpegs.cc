// bench_decode_jpegs LP_FILE [RUNS=5]: the decode limit of fit-ptm. Decodes every photo the .lp
// lists with libjpeg on all cores (JpegRowReader, the decoder fit-ptm streams with; each thread
// decodes into one reused buffer, so nothing but decoding is timed) and prints the best and the
// median wall time of RUNS runs, in seconds.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "core/image_u8_io.h"
#include "core/parallel.h"
#include "formats/lp_file.h"

int main(int argc, char** argv) {
  using namespace mesocap;
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_decode_jpegs LP_FILE [RUNS]\n");
    return 2;
  }
  auto entries = ReadLpFile(argv[1], /*require_images_exist=*/true);
  if (!entries.ok()) {
    std::fprintf(stderr, "%s\n", entries.status().message().c_str());
    return 1;
  }
  const int runs = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
  std::vector<double> seconds;
  for (int run = 0; run < runs; ++run) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<int> failed(entries->size(), 0);
    ParallelFor(0, int(entries->size()), [&](int i) {
      auto reader = JpegRowReader::Open((*entries)[size_t(i)].image, 3);
      if (!reader.ok() || !*reader) {
        failed[size_t(i)] = 1;
        return;
      }
      thread_local std::vector<uint8_t> rows;
      JpegRowReader& jpeg = **reader;
      const size_t row_bytes = size_t(jpeg.width()) * jpeg.channels();
      rows.resize(16 * row_bytes);
      uint8_t* pointers[16];
      for (int r = 0; r < 16; ++r) pointers[r] = rows.data() + r * row_bytes;
      for (int y = 0; y < jpeg.height(); y += 16)
        if (!jpeg.ReadRows(std::min(16, jpeg.height() - y), pointers).ok()) failed[size_t(i)] = 1;
    });
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    if (std::count(failed.begin(), failed.end(), 1) > 0) {
      std::fprintf(stderr, "bench_decode_jpegs: some photos are not baseline JPEGs or failed to decode\n");
      return 1;
    }
  }
  std::sort(seconds.begin(), seconds.end());
  std::printf("decode %zu JPEGs on all cores: best %.3f s, median %.3f s (%d runs)\n", entries->size(), seconds.front(),
              seconds[seconds.size() / 2], runs);
  return 0;
}

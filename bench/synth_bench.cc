// Synthesis speeds at the settings, one run, figures on stdout:
//   roller analysis of an 81-slice view (128x128), quilting 512x512 from one RGB slice and from the
//   81-slice BTF (SVD n = 40), FFT matching against the brute-force spatial SSD (ratio), and PTM
//   block synthesis (the PTM fitted to the 81 slices, Legendre basis) of 512x512 with 30x30 blocks,
//   rejection search against brute force (ratio).
// Usage: bench_synth [WORK_DIR]   (renders the virtual rig's weave once into WORK_DIR)
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "bench/bench_exemplar.h"
#include "reconstruct/ptm.h"
#include "reconstruct/ptm_legendre.h"
#include "synth/block_synthesis.h"
#include "synth/exemplar.h"
#include "synth/patch_matching.h"
#include "synth/quilt.h"
#include "synth/roller.h"

using namespace mesocap;

static double Since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

int main(int argc, char** argv) {
  const std::filesystem::path work = argc > 1 ? argv[1] : std::filesystem::temp_directory_path() / "mesocap_synth_bench";
  const auto folder = bench::Weave81(work);
  if (folder.empty()) return 1;
  auto t = std::chrono::steady_clock::now();
  auto e = LoadExemplar(folder);
  if (!e.ok()) return std::fprintf(stderr, "%s\n", e.status().message().c_str()), 1;
  const double svd = Since(t);
  std::printf("SVD of 81 slices (128x128, n = 40, streamed): %.2f s, energy kept %.5f\n", svd, e->svd_energy_kept);

  Image lum(128, 128, 1);
  for (size_t i = 0; i < lum.pixel_count(); ++i) lum.data()[i] = e->preview.data()[3 * i + 1];
  RollerOptions ro;
  ro.tiles = 3;
  RollerReport rr;
  t = std::chrono::steady_clock::now();
  auto tiles = AnalyseRoller(e->features, lum, ro, &rr);
  std::printf("roller analysis, 81-slice view, 3 tiles: %.3f s (+ SVD %.2f s = %.2f s; target 5 s)\n", Since(t), svd, Since(t) + svd);

  QuiltOptions qo;
  qo.width = qo.height = 512;
  QuiltReport qr;
  t = std::chrono::steady_clock::now();
  auto rgb = QuiltSynthesis(e->preview, qo, &qr);
  std::printf("quilt 512x512 from RGB 128x128: %.2f s (target 3 s; %d patches, match %.2f s, cut %.2f s)\n", Since(t),
              qr.patches, qr.seconds_matching, qr.seconds_cutting);
  t = std::chrono::steady_clock::now();
  auto btf = QuiltSynthesis(e->features, qo, &qr);
  std::printf("quilt 512x512 from the 81-slice BTF (40 features): %.2f s + SVD %.2f s = %.2f s (target 15 s; %d patches)\n",
              Since(t), svd, Since(t) + svd, qr.patches);

  // Matching one 65x65 window (half synthesized) over the 128x128 sample, 40 channels.
  Image out(192, 192, e->features.channels());
  std::vector<uint8_t> synthesized(192 * 192, 0);
  for (int y = 0; y < 192; ++y)
    for (int x = 0; x < 192; ++x) {
      std::copy_n(e->features.pixel(x % 128, y % 128), out.channels(), out.pixel(x, y));
      synthesized[y * 192 + x] = x < 80;
    }
  std::vector<RotatedSample> copies{MakeRotatedSample(e->features, Image(), 0)};
  PatchMatcher matcher(copies, {});
  MatchWindow w{65, 65, &out, &synthesized, nullptr, 40, 40};
  int vw, vh;
  t = std::chrono::steady_clock::now();
  for (int k = 0; k < 10; ++k) matcher.Costs(w, 0, &vw, &vh);
  const double fft = Since(t) / 10;
  t = std::chrono::steady_clock::now();
  BruteForceCosts(copies[0], w, 0, &vw, &vh);
  const double brute = Since(t);
  std::printf("matching a 65x65 window, 40 channels: FFT %.4f s, brute force %.3f s, ratio %.0fx\n", fft, brute, brute / fft);

  // PTM block synthesis: the head-on view's PTM from its 81 lights, in the Legendre basis.
  std::vector<Image> photos;
  std::vector<Eigen::Vector3d> lights;
  for (int k = 0; k < int(e->slices.size()); ++k) photos.push_back(*e->ReadSlice(k)), lights.push_back(e->slices[k].light);
  PtmFitOptions fit;
  fit.format = PtmFormat::kRgb;
  auto ptm = FitPtm(photos, lights, fit);
  if (!ptm.ok()) return std::fprintf(stderr, "%s\n", ptm.status().message().c_str()), 1;
  const Image legendre = PtmLegendreCoefficients(*ptm);
  BlockSynthesisOptions bo;
  bo.width = bo.height = 512;
  double seconds[2];
  BlockSynthesisReport br[2];
  for (BlockSearch search : {BlockSearch::kRejection, BlockSearch::kBruteForce}) {
    bo.search = search;
    const int i = search == BlockSearch::kRejection ? 0 : 1;
    t = std::chrono::steady_clock::now();
    if (!BlockSynthesis(legendre, bo, &br[i]).ok()) return 1;
    seconds[i] = Since(t);
  }
  std::printf("PTM block synthesis 512x512, 30x30 blocks, 128x128 sample: rejection search %.2f s (basis %.2f s, %.1f%% of "
              "candidates rejected on their bound; target 2 s), brute force %.2f s, ratio %.1fx; same map: by construction "
              "(tested)\n",
              seconds[0], br[0].seconds_basis, 100 * br[0].rejected_fraction, seconds[1], seconds[1] / seconds[0]);
  bo.search = BlockSearch::kRejection;
  bo.basis = BlockBasis::kWalshHadamard;
  BlockSynthesisReport walsh;
  t = std::chrono::steady_clock::now();
  if (!BlockSynthesis(legendre, bo, &walsh).ok()) return 1;
  std::printf("  the same with the Walsh-Hadamard basis instead of the principal directions: %.2f s (basis %.2f s), %.1f%% "
              "rejected on their bound, %ld full distances against %ld\n",
              Since(t), walsh.seconds_basis, 100 * walsh.rejected_fraction, walsh.full_distances, br[0].full_distances);
  return tiles.ok() && rgb.ok() && btf.ok() ? 0 : 1;
}

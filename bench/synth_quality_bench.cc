// Synthesis quality on one photograph, as the synthesis issue measures it: each method's map from a
// crop of the sample, applied to the crop, against random-offset tiling of 24 x 24 sample patches
// (the one baseline of every method). Per method and seed: the seam ratio, the subband distance and
// the Laplacian/gradient distance (each also as a ratio to random tiling's, mean of its seeds), the
// repeat share, the share of sample texels used, the largest coherent region, and the seconds.
// Writes a contact sheet (sample | each method's first seed) when --sheet is given.
// Method `resynth` is the peer, GIMP's Resynthesizer engine (bench/resynth_peer/build.sh; its
// executable given by --peer): it fills a size x size canvas from the crop placed in its corner,
// and is scored on the rows below the crop (wholly outside the sample), from the source
// coordinates it reports.
//
// With --ptm the sample becomes a PTM rendered from the photograph (the photograph as albedo, its
// luminance as a height field of --relief texels, lit from 16 directions and fitted as an RGB PTM);
// the methods then synthesize its Legendre coefficients (block, quilt) and every method, random
// tiling included, is scored on the output relit under two lights (0, 0) and (40, 60) deg, the mean.
// Usage: bench_synth_quality SAMPLE.png [--crop 96] [--size 256] [--methods quilt,texton,block,resynth]
//                            [--seeds 3] [--first-seed 1] [--sheet OUT.png|.jpg] [--peer resynth_fill_serial]
//                            [--k 11] [--jitter 0.5] [--passes 2] [--coherence 0.5]
//                            [--neighbourhood 5] [--levels 0] [--textons 400] [--values 1]
//                            [--randomness 0] [--patch-radius 0] [--whole-sample 1|0]
//                            [--usage-weight 0.5] [--usage-tolerance 0.5]   (quilt)
//                            [--block 30] [--overlap 0] [--exclusion 0] [--tolerance 0.5] [--seam-limit 1.2]
//                            [--balance-usage 1] (block)
//                            [--ptm] [--relief 4]
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "core/directions.h"
#include "core/image_io.h"
#include "reconstruct/ptm.h"
#include "reconstruct/ptm_legendre.h"
#include "synth/block_synthesis.h"
#include "synth/exemplar.h"
#include "synth/quilt.h"
#include "synth/synth_quality.h"
#include "synth/synth_test_support.h"
#include "synth/texton_analysis.h"
#include "synth/texton_synthesis.h"

using namespace mesocap;

namespace {

struct Args {
  std::string sample, sheet, methods = "quilt,texton", peer;
  int crop = 96, size = 256, seeds = 3, first_seed = 1;
  TextonSynthesisOptions texton;
  TextonAnalysisOptions analysis;
  QuiltOptions quilt;
  BlockSynthesisOptions block;
  bool ptm = false;
  double relief = 4;
};

struct Scores {
  double seams = 0, subband = 0, lapgrad = 0, repeat = 0, used = 0, seconds = 0;
  long region = 0;
};

// The mean over the images the map is applied to (the sample, or the PTM's relit images).
Scores Measure(const SynthMap& map, const std::vector<Image>& images) {
  Scores s;
  for (const Image& image : images) {
    const Image out = ApplyMapToImage(map, image);
    s.seams += MeasureSeams(map, out, image).ratio() / double(images.size());
    s.subband += SubbandDistance(out, image) / double(images.size());
    s.lapgrad += LaplacianGradientDistance(out, image) / double(images.size());
  }
  const MapUsage u = MeasureMapUsage(map);
  s.repeat = u.repeat_share, s.used = u.used_share, s.region = u.largest_coherent_region;
  return s;
}

StatusOr<SynthMap> Synthesize(const std::string& method, const Image& sample, const TextonAnalysis* textons, const Args& a,
                              uint32_t seed) {
  if (method == "random") return RandomTilingMap(sample.width(), sample.height(), a.size, a.size, 24, seed);
  if (method == "quilt") {
    QuiltOptions o = a.quilt;
    o.width = o.height = a.size;
    o.seed = seed;
    QuiltReport r;
    return QuiltSynthesis(sample, o, &r);
  }
  if (method == "block") {
    BlockSynthesisOptions o = a.block;
    o.width = o.height = a.size;
    o.seed = seed;
    BlockSynthesisReport r;
    return BlockSynthesis(sample, o, &r);
  }
  if (method == "resynth") {
    if (a.peer.empty()) return Status::Error("resynth needs --peer (bench/resynth_peer/build.sh)");
    const auto dir = std::filesystem::temp_directory_path() / ("mesocap_resynth_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    MESOCAP_RETURN_IF_ERROR(WriteImage(dir / "sample.png", sample));
    const std::string command = a.peer + " " + (dir / "sample.png").string() + " " + (dir / "out.png").string() + " " +
                                std::to_string(a.size) + " " + std::to_string(a.size) + " --seed " + std::to_string(seed) +
                                " --coords " + (dir / "out.coords").string() + " 2>/dev/null";
    if (std::system(command.c_str()) != 0) return Status::Error("the peer failed: " + command);
    std::vector<float> coords(size_t(a.size) * a.size * 2);
    std::ifstream in(dir / "out.coords", std::ios::binary);
    in.read(reinterpret_cast<char*>(coords.data()), std::streamsize(coords.size() * sizeof(float)));
    std::filesystem::remove_all(dir);
    if (!in) return Status::Error("the peer wrote no coordinates");
    SynthMap map(a.size, a.size - sample.height(), sample.width(), sample.height(), "resynth");
    for (int y = sample.height(); y < a.size; ++y)
      for (int x = 0; x < a.size; ++x) {
        const float* c = &coords[(size_t(y) * a.size + x) * 2];
        if (c[0] < 0 || c[1] < 0) return Status::Error("the peer left a texel without a source");
        map.Set(x, y - sample.height(), c[0] + 0.5f, c[1] + 0.5f, 0, 0);
      }
    return map;
  }
  if (method == "texton") {
    TextonSynthesisOptions o = a.texton;
    o.width = o.height = a.size;
    o.seed = seed;
    return TextonSynthesis(*textons, o, nullptr);
  }
  return Status::Error("unknown method " + method);
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto next = [&]() { return i + 1 < argc ? std::string(argv[++i]) : std::string(); };
    if (arg == "--crop") a.crop = std::atoi(next().c_str());
    else if (arg == "--size") a.size = std::atoi(next().c_str());
    else if (arg == "--seeds") a.seeds = std::atoi(next().c_str());
    else if (arg == "--first-seed") a.first_seed = std::atoi(next().c_str());
    else if (arg == "--usage-weight") a.quilt.usage_weight = std::atof(next().c_str());
    else if (arg == "--usage-tolerance") a.quilt.usage_tolerance = std::atof(next().c_str());
    else if (arg == "--methods") a.methods = next();
    else if (arg == "--sheet") a.sheet = next();
    else if (arg == "--peer") a.peer = next();
    else if (arg == "--randomness") a.quilt.randomness = std::atof(next().c_str());
    else if (arg == "--patch-radius") a.quilt.patch_radius = std::atoi(next().c_str());
    else if (arg == "--whole-sample") a.quilt.whole_sample = std::atoi(next().c_str()) != 0;
    else if (arg == "--block") a.block.block = std::atoi(next().c_str());
    else if (arg == "--overlap") a.block.overlap = std::atoi(next().c_str());
    else if (arg == "--exclusion") a.block.continuation_exclusion = std::atoi(next().c_str());
    else if (arg == "--tolerance") a.block.tolerance = std::atof(next().c_str());
    else if (arg == "--seam-limit") a.block.seam_limit = std::atof(next().c_str());
    else if (arg == "--balance-usage") a.block.balance_usage = std::atoi(next().c_str()) != 0;
    else if (arg == "--ptm") a.ptm = true;
    else if (arg == "--relief") a.relief = std::atof(next().c_str());
    else if (arg == "--k") a.texton.k = std::atoi(next().c_str());
    else if (arg == "--jitter") a.texton.jitter = std::atof(next().c_str());
    else if (arg == "--coherence") a.texton.coherence = std::atof(next().c_str());
    else if (arg == "--values") a.analysis.texel_value_weight = std::atof(next().c_str());
    else if (arg == "--passes") a.texton.passes = std::atoi(next().c_str());
    else if (arg == "--neighbourhood") a.texton.neighbourhood = std::atoi(next().c_str());
    else if (arg == "--levels") a.analysis.levels = std::atoi(next().c_str());
    else if (arg == "--textons") a.analysis.textons = std::atoi(next().c_str());
    else if (a.sample.empty()) a.sample = arg;
    else return std::fprintf(stderr, "unknown argument %s\n", arg.c_str()), 2;
  }
  if (a.sample.empty()) return std::fprintf(stderr, "usage: bench_synth_quality SAMPLE.png [options]\n"), 2;
  auto photo = ReadImage(a.sample, {true, 3});
  if (!photo.ok()) return std::fprintf(stderr, "%s\n", photo.status().message().c_str()), 1;
  if (photo->width() < a.crop || photo->height() < a.crop) return std::fprintf(stderr, "%s: smaller than the crop\n", a.sample.c_str()), 1;
  Image sample(a.crop, a.crop, photo->channels());
  for (int y = 0; y < a.crop; ++y)
    for (int x = 0; x < a.crop; ++x)
      for (int c = 0; c < sample.channels(); ++c) sample.at(x, y, c) = photo->at(x, y, c);

  // What the methods synthesize (features) and what the scores look at (images).
  Image features = sample;
  std::vector<Image> images{sample};
  if (a.ptm) {
    const Ptm ptm = testing::PhotoReliefPtm(sample, a.relief);
    features = PtmLegendreCoefficients(ptm);
    images = {RelightPtm(ptm, DirectionFromAnglesDeg(0, 0)), RelightPtm(ptm, DirectionFromAnglesDeg(40, 60))};
  }

  std::vector<std::string> methods{"random"};
  std::stringstream list(a.methods);
  for (std::string m; std::getline(list, m, ',');) methods.push_back(m);
  TextonAnalysis textons;
  double analysis_seconds = 0;
  for (const std::string& m : methods)
    if (m == "texton") {
      const Exemplar e = ImageExemplar(images[0]);
      auto r = AnalyzeTextons(AppearanceImageCount(e), [&](int k) { return AppearanceLuminance(e, k); }, a.analysis);
      if (!r.ok()) return std::fprintf(stderr, "%s\n", r.status().message().c_str()), 1;
      textons = std::move(*r);
      analysis_seconds = textons.seconds;
    }

  Image sheet;
  if (!a.sheet.empty()) sheet = Image((a.size + 8) * int(methods.size() + 1), a.size, sample.channels(), 1.0f);
  auto paste = [&](const Image& img, int column) {
    for (int y = 0; y < img.height(); ++y)
      for (int x = 0; x < img.width(); ++x)
        for (int c = 0; c < img.channels(); ++c) sheet.at(column * (a.size + 8) + x, y, c) = img.at(x, y, c);
  };
  if (!sheet.empty()) paste(images[0], 0);

  Scores baseline;
  std::printf("%-28s %-8s %6s %8s %8s %8s %8s %7s %6s %7s %6s\n", "sample", "method", "seams", "subband", "xrandom", "lapgrad",
              "xrandom", "repeat", "used", "region", "sec");
  for (size_t m = 0; m < methods.size(); ++m) {
    Scores mean;
    for (int s = 0; s < a.seeds; ++s) {
      const auto start = std::chrono::steady_clock::now();
      auto map = Synthesize(methods[m], methods[m] == "resynth" || methods[m] == "texton" ? images[0] : features, &textons, a,
                            uint32_t(a.first_seed + s));
      if (!map.ok()) return std::fprintf(stderr, "%s: %s\n", methods[m].c_str(), map.status().message().c_str()), 1;
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      Scores sc = Measure(*map, images);
      mean.seams += sc.seams / a.seeds, mean.subband += sc.subband / a.seeds, mean.lapgrad += sc.lapgrad / a.seeds;
      mean.repeat += sc.repeat / a.seeds, mean.used += sc.used / a.seeds, mean.seconds += seconds / a.seeds;
      mean.region = std::max(mean.region, sc.region);
      if (s == 0 && !sheet.empty()) paste(ApplyMapToImage(*map, images[0]), int(m) + 1);
    }
    if (m == 0) baseline = mean;
    if (methods[m] == "texton") mean.seconds += analysis_seconds;
    std::printf("%-28s %-8s %6.3f %8.5f %8.3f %8.5f %8.3f %7.4f %6.3f %7ld %6.2f\n",
                std::filesystem::path(a.sample).filename().string().c_str(), methods[m].c_str(), mean.seams, mean.subband,
                mean.subband / baseline.subband, mean.lapgrad, mean.lapgrad / baseline.lapgrad, mean.repeat, mean.used,
                mean.region, mean.seconds);
  }
  if (!sheet.empty()) {
    const Status st = WriteImage(a.sheet, sheet);
    if (!st.ok()) return std::fprintf(stderr, "%s\n", st.message().c_str()), 1;
  }
  return 0;
}

#include "app/demo_synthesis.h"

#include <array>
#include <chrono>
#include <cstdio>

#include "app/session_stages.h"
#include "app/synth_run.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "core/session_layout.h"
#include "core/text_format.h"
#include "export/previews.h"
#include "synth/synth_quality.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;

// Each exemplar enlarged to twice its side.
constexpr int kEnlargement = 2;

// The three lights of the pictures (theta, phi in degrees), the view head-on.
const std::array<Eigen::Vector3d, 3>& PreviewLights() {
  static const std::array<Eigen::Vector3d, 3> lights = {DirectionFromAnglesDeg(0, 0), DirectionFromAnglesDeg(45, 30),
                                                        DirectionFromAnglesDeg(60, 200)};
  return lights;
}

// The sample under the preview lights: for a BTF the slices nearest each light at the most
// head-on view, for a PTM its relighting.
StatusOr<std::vector<Image>> SampleUnderPreviewLights(const Exemplar& e) {
  std::vector<Image> images;
  for (const Eigen::Vector3d& light : PreviewLights()) {
    if (e.kind == ExemplarKind::kPtm) {
      images.push_back(RelightPtm(e.ptm, light, /*clamp=*/false));
      continue;
    }
    int best = 0;
    double best_cost = 1e300;
    for (int k = 0; k < int(e.slices.size()); ++k) {
      const double cost = 10 * (1 - e.slices[size_t(k)].view.z()) + (1 - e.slices[size_t(k)].light.dot(light));
      if (cost < best_cost) best_cost = cost, best = k;
    }
    auto slice = e.ReadSlice(best);
    if (!slice.ok()) return slice.status();
    images.push_back(std::move(*slice));
  }
  return images;
}

struct MethodRun {
  std::string method, exemplar;
  double seconds = 0;
  std::vector<double> seam_ratios;
  std::vector<Image> previews;
};

StatusOr<MethodRun> RunMethod(const std::string& method, const Exemplar& e, const std::vector<Image>& sample_images) {
  SynthMethodOptions options;
  options.method = method;
  // Textons: 24 representative slices chosen by K-means (Tong §4) rather than every slice.
  options.texton_analysis.representative_slices = 24;
  options.width = kEnlargement * e.width, options.height = kEnlargement * e.height;
  Json report;
  std::string note;
  const auto start = std::chrono::steady_clock::now();
  auto map = RunSynthesisMethod(e, options, &report, &note);
  if (!map.ok()) return Status::Error(method + ": " + map.status().message());
  MethodRun run;
  run.method = method;
  run.exemplar = e.kind == ExemplarKind::kPtm ? "top board's PTM" : "reconstructed BTF";
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (const Image& sample : sample_images) {
    run.previews.push_back(ApplyMapToImage(*map, sample));
    run.seam_ratios.push_back(MeasureSeams(*map, run.previews.back(), sample).ratio());
  }
  std::printf("demo: synthesis %s of the %s: %.1f s, seam ratio %.2f / %.2f / %.2f under three lights\n", method.c_str(),
              run.exemplar.c_str(), run.seconds, run.seam_ratios[0], run.seam_ratios[1], run.seam_ratios[2]);
  return run;
}

}  // namespace

Status AddSynthesisToDemo(const fs::path& out, const fs::path& session, int top_board, StageClock* clock, Report* report) {
  clock->Start("synthesis: the BTF's features (SVD)");
  auto btf = LoadExemplar(SessionLayout(session).btf().root);
  if (!btf.ok()) return btf.status();
  auto ptm = LoadExemplar(SessionLayout(session).ptm().board_ptm(top_board));
  if (!ptm.ok()) return ptm.status();
  auto btf_images = SampleUnderPreviewLights(*btf), ptm_images = SampleUnderPreviewLights(*ptm);
  if (!btf_images.ok()) return btf_images.status();
  if (!ptm_images.ok()) return ptm_images.status();
  std::vector<MethodRun> runs;
  for (const auto& [method, exemplar, images] : {std::tuple{"roller", &*btf, &*btf_images}, {"quilt", &*btf, &*btf_images},
                                                 {"texton", &*btf, &*btf_images}, {"ptm-block", &*ptm, &*ptm_images}}) {
    clock->Start(std::string("synthesis: ") + method);
    auto run = RunMethod(method, *exemplar, *images);
    if (!run.ok()) return run.status();
    runs.push_back(std::move(*run));
  }
  clock->Start("synthesis: pictures");
  // One row per light: the BTF sample, its roller, quilt and texton enlargements, the PTM sample
  // and its block synthesis; one exposure per row.
  std::vector<Image> pictures;
  std::vector<std::string> labels;
  for (size_t k = 0; k < PreviewLights().size(); ++k) {
    const std::vector<Image> row = ExposeAll({(*btf_images)[k], runs[0].previews[k], runs[1].previews[k], runs[2].previews[k],
                                              (*ptm_images)[k], runs[3].previews[k]});
    pictures.insert(pictures.end(), row.begin(), row.end());
    for (const char* what : {"BTF sample", "roller", "quilt", "texton", "PTM sample", "ptm-block"})
      labels.push_back(Format("%s, light %zu", what, k + 1));
  }
  MESOCAP_RETURN_IF_ERROR(WriteImage(out / "synthesis.jpg", ContactSheet(pictures, labels, 6, 200), {.format = PixelFormat::kUint8Srgb}));
  std::vector<std::vector<std::string>> rows;
  for (const MethodRun& run : runs)
    rows.push_back({run.method, run.exemplar, Format("%.1f", run.seconds), Format("%.2f", run.seam_ratios[0]),
                    Format("%.2f", run.seam_ratios[1]), Format("%.2f", run.seam_ratios[2])});
  report->Heading("Synthesis");
  report->Paragraph(Format(
      "The session's reconstructed BTF (%dx%d, %zu slices; matched on %d SVD features) enlarged to %dx%d by the BTF roller, "
      "by graphcut quilting and by 3D textons with the k-coherence search (k = 11, textons of 24 representative slices), "
      "and the top board's PTM (%dx%d, matched in the Legendre basis) to %dx%d by block "
      "synthesis with the exact rejection search (`mesocap synth`). Seam ratio: the mean step across the cuts over the "
      "sample's own mean neighbour step, under each light (1 is invisible; the issue asks at most 1.2).",
      btf->width, btf->height, btf->slices.size(), btf->features.channels(), kEnlargement * btf->width,
      kEnlargement * btf->height, ptm->width, ptm->height, kEnlargement * ptm->width, kEnlargement * ptm->height));
  report->Table({"method", "exemplar", "seconds", "seam ratio light 1", "light 2", "light 3"}, rows);
  report->Picture("synthesis.jpg", "Under three lights (rows; head-on view): the BTF sample, the roller, quilting, "
                                   "textons, the PTM sample, block synthesis; each output has twice its sample's side");
  return Status::Ok();
}

}  // namespace mesocap::app

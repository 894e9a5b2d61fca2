// mesocap evaluate: the paper's validation on the virtual rig. Renders a material's true BTF at
// the rig's 13 views under the Bonn 81 lights (or, with --session, takes a virtual session's
// calibrated slices: the lights a hand-held flash gave each board), reconstructs the held-out
// pairs of the Bonn 81 x 81 grid, and scores them against truth next to the two baselines.
// Writes evaluation.json (every pair), evaluation.csv, a picture sheet and report.md/html.
#include "app/evaluate_args.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>

#include "app/commands.h"
#include "capture/btf_render.h"
#include "capture/rig_render.h"
#include "capture/rig_scene.h"
#include "capture/true_btf_renderer.h"
#include "core/atomic_file.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "core/provenance.h"
#include "core/session.h"
#include "core/session_layout.h"
#include "export/previews.h"
#include "export/report.h"
#include "app/btf_method_args.h"
#include "reconstruct/btf_evaluation.h"
#include "reconstruct/slice_set.h"

namespace mesocap::app {
namespace {

// Truth / statistical / top view / BRDF-modulated for a few held-out pairs, each row exposed
// by its truth so the methods compare at one brightness.
Image PictureSheet(const StatisticalBtf& btf, const TrueSliceFn& truth) {
  const double pairs[][4] = {{45, 90, 15, 0}, {60, 180, 45, 40}, {30, 0, 60, 18}, {75, 270, 75, 0}};
  std::vector<Image> cells;
  std::vector<std::string> labels;
  for (const auto& p : pairs) {
    const Eigen::Vector3d light = DirectionFromAnglesDeg(p[0], p[1]), view = DirectionFromAnglesDeg(p[2], p[3]);
    const Image t = truth(light, view);
    const auto methods = ReconstructAllMethods(btf, light, view, t);
    for (const Image& cell : ExposeTogether({t, methods[0], methods[1], methods[2]})) cells.push_back(cell);
    labels.push_back(Format("truth i(%g,%g) o(%g,%g)", p[0], p[1], p[2], p[3]));
    for (int m = 0; m < kBtfMethods; ++m) labels.push_back(BtfMethodToString(BtfMethod(m)));
  }
  return ContactSheet(cells, labels, 4, 200);
}

// Samples per texel axis of the true slices (--samples-per-axis 0 chooses): from a session's
// shots, what the rig's camera can see (RigTruthSamplesPerAxis); from the true BTF's views, 2 x 2
// as the inputs are rendered.
int TruthSamplesPerAxis(const EvaluateArgs& a, bool session) {
  if (a.samples_per_axis > 0) return a.samples_per_axis;
  if (!session) return 2;  // inputs and targets alike: a consistent camera
  return RigTruthSamplesPerAxis(a.size);
}

// The material and layout a virtual session was rendered with, from its truth.json.
StatusOr<RigScene> SessionTruth(const std::filesystem::path& session) {
  const std::filesystem::path file = SessionLayout(session).truth();
  if (!std::filesystem::exists(file))
    return Status::Error(file.string() + " not found: --session scores a virtual session (mesocap simulate), whose true "
                         "BTF is known");
  auto json = ReadJsonFile(file);
  if (!json.ok()) return json.status();
  auto scene = TruthFromJson(*json);
  if (!scene.ok()) return Status::Error(file.string() + ": " + scene.status().message());
  return scene;
}

// The statistical BTF of the session's slices (SESSION/slices from `mesocap calibrate`) scored
// by `truth`, once `renderer` has the true BTF of `material` (which must outlive it) at the
// session's top board's patch.
StatusOr<BtfEvaluation> EvaluateSession(const EvaluateArgs& a, const RigScene& scene, const Material& material,
                                        const BtfEvaluationOptions& options, std::optional<TrueBtfRenderer>* renderer,
                                        const TrueSliceFn& truth, std::optional<StatisticalBtf>* model,
                                        const ProgressFn& progress) {
  SliceSetOptions slices;
  slices.btf = options.btf;
  slices.size = a.size;
  a.method.ApplyTo(&slices);  // the slices' shots decide where the chromaticity comes from, unless forced
  SliceSetReport loaded;
  const std::filesystem::path index = SessionLayout(a.session).slices().index();
  if (!std::filesystem::exists(index)) return Status::Error(index.string() + " not found: run `mesocap calibrate` first");
  auto btf = LoadStatisticalBtf(index, slices, &loaded, progress);
  if (!btf.ok()) return btf.status();
  for (const std::string& warning : loaded.warnings) std::fprintf(stderr, "evaluate: %s\n", warning.c_str());
  const auto top = std::find_if(scene.boards.begin(), scene.boards.end(), [&](const RigBoard& b) { return b.id == loaded.top_board; });
  if (top == scene.boards.end()) return Status::Error(Format("board %d of the slices is not in %s", loaded.top_board,
                                                                SessionLayout("").truth().string().c_str()));
  TrueBtfRequest grid;
  grid.size = btf->width();
  grid.samples_per_axis = TruthSamplesPerAxis(a, true);
  grid.patch_m = top->patch_m;
  grid.offset_m = top->material_offset_m;
  renderer->emplace(material, grid);
  auto eval = ScoreHeldOutPairs(*btf, truth, options, progress);
  if (!eval.ok()) return eval.status();
  eval->input_slices = loaded.slices_used;
  eval->seconds_statistics = loaded.seconds;
  *model = std::move(*btf);
  return eval;
}

// How the colour was moved toward white (StatisticalBtfOptions::white_specular_colour).
std::string WhiteLobeSentence(const WhiteLobe& lobe) {
  if (!(lobe.strength() > 0)) return ", no white specular lobe fitted";
  const Eigen::Vector3d& b = lobe.body_chromaticity();
  return Format(", moved toward white by a white specular lobe fitted to the measured mean colours (strength %.2f, "
                "roughness %.2f, body chromaticity %.3f, %.3f, %.3f)",
                lobe.strength(), lobe.alpha(), b.x(), b.y(), b.z());
}

// Whether the mean brightness model was used (StatisticalBtfOptions::mean_model).
std::string MeanModelSentence(const StatisticalBtf& btf) {
  if (!btf.options().mean_model) return " The mean brightness model is off.";
  const MeanModelCheck& check = btf.mean_model_check();
  if (check.slices == 0) return " The mean brightness model is not used: no tilted view to check it on, or too few slices.";
  return Format(" Beyond the measured lights, slices take the mean brightness of a model fitted to every measured "
                "slice%s: it predicts each tilted view's slices, fitted without them, within %.1f%% (median), the top "
                "view within %.1f%%.",
                check.used ? "" : " (not used: no nearer than the top view)", 100 * std::expm1(check.model_error),
                100 * std::expm1(check.top_view_error));
}

// Which images of the material the views borrowed lights from (StatisticalBtfOptions::mirror_symmetry).
std::string MirrorSymmetrySentence(const StatisticalBtf& btf) {
  if (!btf.options().mirror_symmetry) return "";
  const MirrorSymmetryCheck& check = btf.symmetry_check();
  if (!check.tested) return " No image of the material could be tested (too few top-view lights).";
  std::string held, failed;
  for (size_t k = 0; k < MirrorImages().size(); ++k) {
    std::string& list = check.holds[k] ? held : failed;
    list += Format("%s%s (%.2f, %.2f)", list.empty() ? "" : ", ", MirrorImages()[k].name, check.ratio[k],
                   check.against_measured[k]);
  }
  return Format(" Views also borrow the lights of their images under: %s; not under: %s (top-view statistics imaged "
                "against those at the imaged light: median distance over the interpolation's own, at most %.1f, and "
                "over the unimaged statistics', at most %.2f).",
                held.empty() ? "none" : held.c_str(), failed.empty() ? "none" : failed.c_str(), kMirrorCheckLimit,
                kMirrorCheckTolerance);
}

}  // namespace

int RunEvaluate(EvaluateArgs& a) {
  std::optional<RigScene> scene;
  if (!a.session.empty()) {
    auto truth = SessionTruth(a.session);
    if (!truth.ok()) return Fail("evaluate", truth.status().message(), kExitUsage);
    scene = std::move(*truth);
    if (std::string named = a.method.TakeSessionMirrorImages(a.session); !named.empty())
      std::fprintf(stderr, "evaluate: images the capture was guided by: %s (--mirror-images overrides)\n", named.c_str());
  }
  const std::string material_name = scene ? scene->options.material : a.material;
  auto material = Material::Create(material_name);
  if (!material.ok()) return Fail("evaluate", material.status().message(), kExitUsage);
  if (a.size < 16 || (a.size & (a.size - 1)) != 0) return Fail("evaluate", "--size must be a power of two >= 16", kExitUsage);
  if (a.pairs == 0 || a.pairs < -1) return Fail("evaluate", "--pairs must be a positive count, or -1 for all", kExitUsage);
  if (!IsMissingOrEmptyDir(a.out)) return Fail("evaluate", a.out.string() + ": exists and is not empty", kExitUsage);
  auto staging = StagingFolder::Begin(a.out);  // the folder appears whole, at the end
  if (!staging.ok()) return Fail("evaluate", staging.status());
  const std::filesystem::path out = staging->path();

  BtfEvaluationOptions options;
  options.btf.num_threads = a.threads;
  options.btf.match_subbands = !a.pixel_only;
  options.max_pairs = a.pairs;
  options.btf.max_view_extrapolation = a.max_view_extrapolation;
  a.method.ApplyTo(&options.btf);  // the colour space was checked by CLI11
  ProgressBar bar("evaluate", !a.no_progress);
  std::optional<TrueBtfRenderer> renderer;  // each view traced once, for all its lights
  const TrueSliceFn truth = [&](const Eigen::Vector3d& light, const Eigen::Vector3d& view) {
    return renderer->Render(light, view);  // parallel over slices, not inside one
  };
  std::optional<StatisticalBtf> model;
  StatusOr<BtfEvaluation> eval = Status::Error("not evaluated");
  if (scene) {
    eval = EvaluateSession(a, *scene, *material, options, &renderer, truth, &model, bar.AsCallback());
  } else {
    TrueBtfRequest grid;
    grid.size = a.size;
    grid.samples_per_axis = TruthSamplesPerAxis(a, false);
    renderer.emplace(*material, grid);
    eval = EvaluateStatisticalBtf(truth, options, bar.AsCallback(), &model);
  }
  if (!eval.ok())
    return Fail("evaluate", eval.status());

  const int truth_samples = TruthSamplesPerAxis(a, bool(scene));
  Json j = eval->ToJson();
  j["material"] = material_name;
  j["size"] = a.size;
  j["truth_samples_per_axis"] = truth_samples;
  if (scene) j["session"] = a.session.string();
  j["chroma_from_top"] = model->options().chromaticity_from_top_view;
  j["white_lobe"] = model->white_lobe().ToJson();
  j["mean_model"] = model->mean_model_check().ToJson();
  j["mirror_symmetry"] = model->symmetry_check().ToJson();
  Json settings = a.method.ToJson();
  settings.update({{"material", material_name}, {"session", a.session.string()}, {"size", a.size}, {"pairs", a.pairs},
                   {"samples_per_axis", truth_samples},
                   {"pixel_only", a.pixel_only}});
  j["provenance"] = MakeProvenance(settings);
  if (Status st = WriteJsonFile(out / "evaluation.json", j); !st.ok()) return Fail("evaluate", st);
  std::string csv = "theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg";
  for (int m = 0; m < kBtfMethods; ++m)
    for (const char* s : {"rmse", "w_pixels", "w_bands", "w_chromaticity", "saturation_ratio"})
      csv += "," + BtfMethodToString(BtfMethod(m)) + "_" + s;
  csv += "\n";
  for (const PairScore& p : eval->pairs) {
    const Eigen::Vector2d i = AnglesDegFromDirection(p.light), o = AnglesDegFromDirection(p.view);
    csv += Format("%.2f,%.2f,%.2f,%.2f", i.x(), i.y(), o.x(), o.y());
    for (int m = 0; m < kBtfMethods; ++m)
      csv += Format(",%.6g,%.6g,%.6g,%.6g,%.6g", p.rmse[m], p.wasserstein_pixels[m], p.wasserstein_bands[m],
                    p.wasserstein_chromaticity[m], p.saturation_ratio[m]);
    csv += "\n";
  }
  if (Status st = WriteTextAtomically(out / "evaluation.csv", csv); !st.ok()) return Fail("evaluate", st);
  ImageWriteOptions png;
  png.format = PixelFormat::kUint8Srgb;
  if (Status st = WriteImage(out / "sheet.png", PictureSheet(*model, truth), png); !st.ok()) return Fail("evaluate", st);

  Report report("mesocap evaluate: " + material_name);
  const std::string source =
      scene ? Format("from the %d calibrated slices of %zu boards in %s", eval->input_slices, model->views().size(),
                     a.session.string().c_str())
            : std::string("from the rig's 13 views under 81 lights");
  report.Paragraph(Format("Statistical BTF reconstruction (Ngan & Durand 2006) %s, scored on %zu held-out pairs of the "
                          "81 x 81 Bonn grid at %d x %d texels (true slices: the mean of %d x %d samples a texel).",
                          source.c_str(), eval->pairs.size(), model->width(), model->height(),
                          truth_samples, truth_samples));
  const auto rmse = eval->Median(&PairScore::rmse), wp = eval->Median(&PairScore::wasserstein_pixels),
             wb = eval->Median(&PairScore::wasserstein_bands), wc = eval->Median(&PairScore::wasserstein_chromaticity),
             saturation = eval->MedianSaturationError(), worst = eval->WorstSaturationError();
  std::vector<std::vector<std::string>> rows;
  for (int m = 0; m < kBtfMethods; ++m)
    rows.push_back({BtfMethodToString(BtfMethod(m)), Format("%.5f", rmse[m]), Format("%.5f", wp[m]), Format("%.5f", wb[m]),
                    Format("%.5f", wc[m]), Format("%.1f%% / %.1f%%", 100 * saturation[m], 100 * worst[m])});
  report.Table({"method", "median RMSE", "median W1 pixels", "median W1 subbands", "median W1 chromaticity",
                "saturation p95 off by (median / worst)"},
               rows);
  report.Paragraph(Format("The statistical reconstruction beats both baselines on pixel W1 in %.1f%% of pairs, on "
                          "subband W1 in %.1f%% and on chromaticity W1 in %.1f%%. Histograms matched in %s; the "
                          "chromaticity's statistics taken from %s%s.%s%s "
                          "Reconstruction %.1f ms per slice (thread time, all three methods).",
                          100 * eval->FractionBeatingBoth(&PairScore::wasserstein_pixels),
                          100 * eval->FractionBeatingBoth(&PairScore::wasserstein_bands),
                          100 * eval->FractionBeatingBoth(&PairScore::wasserstein_chromaticity),
                          a.method.colour_space.c_str(),
                          model->options().chromaticity_from_top_view ? "the top view" : "every view",
                          WhiteLobeSentence(model->white_lobe()).c_str(), MeanModelSentence(*model).c_str(),
                          MirrorSymmetrySentence(*model).c_str(), eval->reconstruct_ms_per_slice));
  report.Picture("sheet.png", "truth | statistical | top view only | top texture x average BRDF");
  if (Status st = report.Write(out); !st.ok()) return Fail("evaluate", st);
  if (Status st = staging->Publish(); !st.ok()) return Fail("evaluate", st);
  std::printf("%s\n", eval->Brief().c_str());
  return kExitOk;
}
}  // namespace mesocap::app

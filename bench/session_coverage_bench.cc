// Benchmark (issue 12): how the statistical BTF fares on the lights a hand-held flash session
// actually gives each board. For virtual sessions of several shot counts, materials and seeds it
// takes the rig's true geometry (board poses, flash positions; a light below a board's horizon or
// shadowed anywhere on its patch is dropped, as the resample stage drops it), renders each board's
// true slices at the patch centre's directions, reconstructs, and scores held-out Bonn pairs
// against the truth next to both baselines, split by where the pair's light lies against the
// lights its views measured (inside their hull, within 15 deg of one, far outside).
//
// It measures coverage, not calibration: the slices are true directional-light slices, and every
// board sees the material at the top board's place (the statistics are alignment-insensitive);
// with --regions 1, each board sees its own part of the material, as on the rig (its
// material_offset_m), while the top board and the held-out truth keep the top board's.
//
// Usage: bench_session_coverage [--shots 24,50,100,150] [--materials weave,stones,corduroy]
//                               [--seeds 11,12] [--size 64] [--pairs 240] [--colour-space NAME]
//                               [--top-view-prior 0|1] [--far-light-falloff DEG] [--details 1]
//                               [--list-lights 1] [--guided START]
//                               [--predict-shadows 0|1] [--objective spread|near] [--spread-cap DEG]
//                               [--board-weights 0|1]
//                               [--cosine 0|1] [--fit-light-falloff 0|1] [--change-from-top 0|1]
//                               [--true-mean 0|1] [--regions 0|1] [--chroma-from-top 0|1]
//                               [--white-specular 0|1] [--mean-model 0|1] [--mean-onset DEG]
//                               [--max-view-extrapolation RINGS] [--dump-means FILE]
//                               [--dump-shapes FILE] [--guide-images MASK] [--flashes-from TRUTH_JSON]
// With --guided START, a session of START hand-held shots is continued up to each --shots count
// by `mesocap coverage`'s suggestions (reconstruct/light_coverage.h), one at a time. With
// --guide-images MASK (one 0 or 1 per MirrorImages() entry, e.g. 0010000), guidance also counts
// each board's lights' images under those (CoverageOptions::images), as `mesocap coverage` does
// with the images a session's slices show hold; the reconstruction's own check on the virtual
// materials finds weave 0010000, stones 1111111, corduroy 1110000.
// With --flashes-from TRUTH_JSON, the flashes are a session's (its truth.json's shots, e.g. a
// guided virtual `mesocap capture`), on the rig of --seeds' single seed: what that session's
// lights give with true slices, against what its calibrated slices give (`mesocap evaluate`).
// With --details 1: the white specular lobe fitted (reconstruct/white_lobe.h); the colour
// saturation error (median and worst pair, and which pair); per class of pairs (inside, near,
// far), which baseline the losses go to; the wins by the view's incidence and by the light's angle
// to the view's mirror direction; and how many far pairs have a light that no flash position could
// give the board nearest their view (below its horizon or shadowed from every position).
// With --dump-means FILE (a diagnostic), every measured slice's mean and, per scored pair, the
// truth's and the reconstruction's (and the pair's pixel W1 of the three methods) are appended to
// FILE as CSV (the mean model was chosen so). With --dump-shapes FILE, the same for the brightness
// quantile functions, with the two baselines' (to study the distribution's shape beyond its mean).
// With --true-mean 1 (a diagnostic): each reconstruction is scaled per channel to the truth's mean
// before it is scored, so the figures tell how much a known mean radiance would win.
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "app/coverage_output.h"
#include "capture/btf_render.h"
#include "capture/true_btf_renderer.h"
#include "capture/rig_render.h"
#include "capture/rig_scene.h"
#include "core/directions.h"
#include "core/json.h"
#include "reconstruct/btf_evaluation.h"
#include "reconstruct/light_coverage.h"

namespace mesocap {
namespace {

std::vector<std::string> Split(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, ',');) parts.push_back(part);
  return parts;
}

struct BoardInputs {
  Eigen::Vector3d view;
  std::vector<Eigen::Vector3d> lights;
};

// Each board's view and the flash directions it measured from `flashes` (camera frame; patch
// frame directions at the patch centre).
// Whether the flash at `flash` lights board b's patch: none of 3x3 points on it in shadow.
bool Lit(const RigScene& scene, const RigRenderer& renderer, int b, const Eigen::Vector3d& flash) {
  const RigBoard& board = scene.boards[b];
  for (const double u : {-0.5, 0.0, 0.5})
    for (const double v : {-0.5, 0.0, 0.5}) {
      const Eigen::Vector3d p = board.R * Eigen::Vector3d(u * board.patch_m, v * board.patch_m, 0) + board.t;
      if (renderer.Occluded(p, flash, RigRenderer::kBoard, b)) return false;
    }
  return true;
}

std::vector<BoardInputs> MeasuredLights(const RigScene& scene, const RigRenderer& renderer,
                                        const std::vector<Eigen::Vector3d>& flashes) {
  std::vector<BoardInputs> boards;
  for (int b = 0; b < int(scene.boards.size()); ++b) {
    const RigBoard& board = scene.boards[b];
    BoardInputs measured;
    measured.view = (-board.R.transpose() * board.t).normalized();
    for (const Eigen::Vector3d& flash : flashes) {
      const Eigen::Vector3d light = (board.R.transpose() * (flash - board.t)).normalized();
      if (light.z() <= 0.02) continue;  // below the horizon (theta_i > 88.9 deg)
      const bool shadowed = !Lit(scene, renderer, b, flash);
      bool duplicate = false;
      for (const auto& l : measured.lights) duplicate |= AngleBetweenDeg(l, light) < 0.5;
      if (!shadowed && !duplicate) measured.lights.push_back(light);
    }
    boards.push_back(measured);
  }
  return boards;
}

// The flash positions of a session's truth.json (as `simulate` or a virtual `capture` writes it).
StatusOr<std::vector<Eigen::Vector3d>> FlashesTaken(const std::string& truth_file) {
  auto truth = ReadJsonFile(truth_file);
  if (!truth.ok()) return truth.status();
  std::vector<Eigen::Vector3d> flashes;
  for (const Json& shot : truth->value("shots", Json::array()))
    flashes.push_back(JsonVector3d(shot.at("light_m"), "light_m", 100));
  if (flashes.empty()) return Status::Error(truth_file + ": no shots");
  return flashes;
}

// The rig as a perfect calibration would locate it: boards, balls and grey cards where they are.
CalibrationResult LocatedRig(const RigScene& scene) {
  CalibrationResult rig;
  for (const RigBoard& b : scene.boards) rig.boards.push_back({b.id, true, "", b.R, b.t});
  for (const RigSphere& s : scene.spheres) {
    SphereEstimate ball;
    ball.center_m = s.center_m;
    ball.radius_m = s.radius_m;
    rig.spheres.spheres.push_back(ball);
  }
  for (const RigGreyCard& c : scene.grey_cards) rig.grey_cards.push_back({c.R, c.t, c.patch_m, c.albedo});
  return rig;
}

// The session's own flashes, then (guided) one `mesocap coverage` suggestion after another up to
// `total` shots, each recomputed from what the boards measured so far.
// With `predict_shadows`, the guidance knows which positions shadow which board and suggests only
// positions calibration can use (as `mesocap capture --guide` predicts both from the located rig).
std::vector<Eigen::Vector3d> Flashes(const RigScene& scene, const RigRenderer& renderer, int total, bool predict_shadows,
                                     CoverageObjective objective, double spread_cap_deg, bool board_weights,
                                     bool even_at_pole, const MirrorImageSet& images) {
  std::vector<Eigen::Vector3d> flashes;
  for (const RigShot& shot : scene.shots) flashes.push_back(shot.light_m);
  const Eigen::Vector3d top_centre = scene.boards.front().t;
  const app::FlashUsableFn usable = predict_shadows ? app::FlashUsableTest(LocatedRig(scene), LayoutOf(scene)) : nullptr;
  while (int(flashes.size()) < total) {
    std::vector<BoardLights> boards;
    const std::vector<BoardInputs> inputs = MeasuredLights(scene, renderer, flashes);
    for (int b = 0; b < int(inputs.size()); ++b) boards.push_back({b, scene.boards[b].R, scene.boards[b].t, inputs[b].lights});
    CoverageOptions options;
    options.suggestions = 1;
    options.objective = objective;
    options.spread_cap_deg = spread_cap_deg;
    options.weigh_boards_by_use = board_weights;
    options.view_blend_even_at_pole = even_at_pole;
    options.images = images;
    options.flash_distance_m = MedianFlashDistance(flashes, top_centre);
    LitFn lit;
    if (predict_shadows)
      lit = app::SuggestableTest([&](int board, const Eigen::Vector3d& flash) { return Lit(scene, renderer, board, flash); },
                                 usable);
    const CoverageReport report = AssessCoverage(boards, 0, options, lit);  // board 0 is the top
    if (report.next.empty()) break;
    flashes.push_back(report.next.front().position_cam);
  }
  return flashes;
}

// Far pairs whose light no flash position `mesocap coverage` considers (15-80 deg above the top
// board, every azimuth, unshadowed) could give the board whose view is nearest the pair's, and how
// many of those the reconstruction won: lights such a rig can never measure for that view.
std::pair<int, int> UnreachableFarPairs(const RigScene& scene, const RigRenderer& renderer,
                                        const std::vector<Eigen::Vector3d>& flashes,
                                        const std::vector<BoardInputs>& inputs, const BtfEvaluation& eval) {
  std::vector<BoardLights> boards;
  for (int b = 0; b < int(inputs.size()); ++b) boards.push_back({b, scene.boards[b].R, scene.boards[b].t, inputs[b].lights});
  CoverageOptions options;
  options.suggestions = 0;
  options.flash_distance_m = MedianFlashDistance(flashes, scene.boards.front().t);
  const LitFn lit = [&](int board, const Eigen::Vector3d& flash) { return Lit(scene, renderer, board, flash); };
  const CoverageReport coverage = AssessCoverage(boards, 0, options, lit);
  const std::vector<Eigen::Vector3d> targets = BonnDirections();
  int unreachable = 0, won = 0;
  for (const PairScore& p : eval.pairs) {
    if (p.coverage != LightCoverage::kFar) continue;
    int nearest_board = 0, nearest_target = 0;
    for (int b = 0; b < int(inputs.size()); ++b)
      if (inputs[b].view.dot(p.view) > inputs[nearest_board].view.dot(p.view)) nearest_board = b;
    for (int k = 0; k < int(targets.size()); ++k)
      if (targets[k].dot(p.light) > targets[nearest_target].dot(p.light)) nearest_target = k;
    if (coverage.boards[nearest_board].targets[nearest_target] != TargetState::kUnreachable) continue;
    const auto& w = p.wasserstein_pixels;
    ++unreachable, won += w[0] < w[1] && w[0] < w[2];
  }
  return {unreachable, won};
}

// A diagnostic dump's CSV file, opened for appending; null (and a line on stderr) if it cannot be.
struct CloseFile {
  void operator()(std::FILE* file) const { std::fclose(file); }
};
std::unique_ptr<std::FILE, CloseFile> OpenDump(const char* flag, const std::string& path) {
  std::unique_ptr<std::FILE, CloseFile> out(std::fopen(path.c_str(), "a"));
  if (!out) std::fprintf(stderr, "%s: cannot open %s\n", flag, path.c_str());
  return out;
}

// A direction or colour as three CSV fields.
std::string Csv(const Eigen::Vector3d& v) {
  char text[96];
  std::snprintf(text, sizeof text, "%.6f,%.6f,%.6f", v.x(), v.y(), v.z());
  return std::string(text);
}

// A diagnostic (--dump-means FILE): appends every measured slice's mean (M lines) and, per scored
// pair, the truth's mean and the reconstruction's, its coverage, whether it was won and the three
// methods' pixel W1 (T lines), as CSV, to study models of the mean.
void DumpMeans(const std::string& path, const std::string& material, const std::string& seed, const StatisticalBtf& btf,
               const BtfEvaluation& eval, const TrueSliceFn& truth) {
  const auto file = OpenDump("--dump-means", path);
  if (!file) return;
  std::FILE* out = file.get();
  for (const MeasuredView& view : btf.views())
    for (size_t i = 0; i < view.lights.size() && i < view.mean_rgb.size(); ++i)
      std::fprintf(out, "M,%s,%s,%s,%s,%s\n", material.c_str(), seed.c_str(), Csv(view.view).c_str(),
                   Csv(view.lights[i]).c_str(), Csv(view.mean_rgb[i]).c_str());
  for (const PairScore& p : eval.pairs) {
    const Eigen::Vector3d true_mean = MeanRgb(truth(p.light, p.view));
    const Eigen::Vector3d mean = MeanRgb(btf.Reconstruct(p.light, p.view));
    const auto& w = p.wasserstein_pixels;
    std::fprintf(out, "T,%s,%s,%s,%s,%s,%s,%s,%d,%.6g,%.6g,%.6g\n", material.c_str(), seed.c_str(), Csv(p.view).c_str(),
                 Csv(p.light).c_str(), Csv(true_mean).c_str(), Csv(mean).c_str(), LightCoverageToString(p.coverage).c_str(),
                 int(w[0] < w[1] && w[0] < w[2]), w[0], w[1], w[2]);
  }
}

// A diagnostic (--dump-shapes FILE): the brightness (R + G + B) quantile function at 33 levels of
// every measured slice (M lines) and, per scored pair, of the truth, the reconstruction, the top
// view and the BRDF-modulated baseline (T lines), to study models of the distribution's shape.
void DumpShapes(const std::string& path, const std::string& material, const std::string& seed, const StatisticalBtf& btf,
                const BtfEvaluation& eval, const TrueSliceFn& truth) {
  const auto file = OpenDump("--dump-shapes", path);
  if (!file) return;
  std::FILE* out = file.get();
  const auto levels = [](const InverseCdf& q) {
    std::string text;
    for (int k = 0; k <= 32; ++k) text += "," + std::to_string(q.At(k / 32.0));
    return text;
  };
  const auto brightness = [](const Image& rgb) {
    std::vector<float> values(rgb.pixel_count());
    for (size_t i = 0; i < values.size(); ++i) values[i] = rgb.data()[3 * i] + rgb.data()[3 * i + 1] + rgb.data()[3 * i + 2];
    return InverseCdfOf(values);
  };
  for (const MeasuredView& view : btf.views())
    for (size_t i = 0; i < view.statistics.size(); ++i)  // the measured lights (borrowed ones repeat them)
      std::fprintf(out, "M,%s,%s,%s,%s%s\n", material.c_str(), seed.c_str(), Csv(view.view).c_str(), Csv(view.lights[i]).c_str(),
                   levels(view.statistics[i].pixels[0]).c_str());
  for (const PairScore& p : eval.pairs) {
    const Image t = truth(p.light, p.view);
    const std::array<Image, kBtfMethods> methods = ReconstructAllMethods(btf, p.light, p.view, t);
    std::string quantiles = levels(brightness(t));
    for (const Image& method : methods) quantiles += levels(brightness(method));
    const auto& w = p.wasserstein_pixels;
    std::fprintf(out, "T,%s,%s,%s,%s,%s,%d,%.6g,%.6g,%.6g%s\n", material.c_str(), seed.c_str(), Csv(p.view).c_str(),
                 Csv(p.light).c_str(), LightCoverageToString(p.coverage).c_str(), int(w[0] < w[1] && w[0] < w[2]), w[0], w[1], w[2],
                 quantiles.c_str());
  }
}

int Run(int argc, char** argv) {
  std::vector<std::string> shots = {"24", "50", "100", "150"}, materials = {"weave", "stones", "corduroy"},
                           seeds = {"11", "12"};
  int size = 64, pairs = 240;
  std::string colour_space = "chromaticity", dump_means, dump_shapes;
  bool mean_model = StatisticalBtfOptions().mean_model;
  double mean_onset = StatisticalBtfOptions().mean_model_onset_deg;
  double max_view_extrapolation = StatisticalBtfOptions().max_view_extrapolation;
  bool even_at_pole = StatisticalBtfOptions().view_blend_even_at_pole;
  bool list_lights = false, top_view_prior = true;
  double far_light_falloff = StatisticalBtfOptions().far_light_falloff_deg;
  bool cosine = StatisticalBtfOptions().cosine_weighted_lights, fit_falloff = StatisticalBtfOptions().fit_light_falloff;
  bool change_from_top = StatisticalBtfOptions().blend_change_from_top;
  bool chroma_from_top = StatisticalBtfOptions().chromaticity_from_top_view;
  bool details = false, true_mean = false, own_regions = false;
  bool white_specular = StatisticalBtfOptions().white_specular_colour;
  int guided_start = 0;
  bool predict_shadows = true;
  CoverageObjective objective = CoverageObjective::kSpread;
  double spread_cap_deg = CoverageOptions().spread_cap_deg;
  bool board_weights = CoverageOptions().weigh_boards_by_use;
  MirrorImageSet guide_images{};
  std::string flashes_from;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i], value = argv[i + 1];
    if (flag == "--shots") shots = Split(value);
    else if (flag == "--materials") materials = Split(value);
    else if (flag == "--seeds") seeds = Split(value);
    else if (flag == "--size") size = std::stoi(value);
    else if (flag == "--pairs") pairs = std::stoi(value);
    else if (flag == "--colour-space") colour_space = value;
    else if (flag == "--list-lights") list_lights = value == "1";
    else if (flag == "--top-view-prior") top_view_prior = value == "1";
    else if (flag == "--details") details = value == "1";
    else if (flag == "--true-mean") true_mean = value == "1";
    else if (flag == "--regions") own_regions = value == "1";
    else if (flag == "--far-light-falloff") far_light_falloff = std::stod(value);
    else if (flag == "--cosine") cosine = value == "1";
    else if (flag == "--fit-light-falloff") fit_falloff = value == "1";
    else if (flag == "--change-from-top") change_from_top = value == "1";
    else if (flag == "--chroma-from-top") chroma_from_top = value == "1";
    else if (flag == "--white-specular") white_specular = value == "1";
    else if (flag == "--guided") guided_start = std::stoi(value);
    else if (flag == "--flashes-from") flashes_from = value;
    else if (flag == "--dump-means") dump_means = value;
    else if (flag == "--dump-shapes") dump_shapes = value;
    else if (flag == "--mean-model") mean_model = value == "1";
    else if (flag == "--mean-onset") mean_onset = std::stod(value);
    else if (flag == "--max-view-extrapolation") max_view_extrapolation = std::stod(value);
    else if (flag == "--even-at-pole") even_at_pole = value == "1";
    else if (flag == "--predict-shadows") predict_shadows = value == "1";
    else if (flag == "--spread-cap") spread_cap_deg = std::stod(value);
    else if (flag == "--board-weights") board_weights = value == "1";
    else if (flag == "--guide-images") {
      for (size_t k = 0; k < guide_images.size() && k < value.size(); ++k) guide_images[k] = value[k] == '1';
    }
    else if (flag == "--objective") objective = value == "near" ? CoverageObjective::kNear : CoverageObjective::kSpread;
    else {
      std::fprintf(stderr, "unknown option %s\n", flag.c_str());
      return 2;
    }
  }
  std::printf("material  shots seed views slices | beats both (pixel W1): all  inside  near  far | pairs inside/near/far"
              " | median W1 statistical / top view | chromaticity wins\n");
  for (const std::string& material_name : materials)
    for (const std::string& shot_count : shots)
      for (const std::string& seed : seeds) {
        RigOptions rig;
        rig.material = material_name;
        rig.shots = guided_start > 0 ? guided_start : std::stoi(shot_count);
        rig.seed = std::stoull(seed);
        rig.width = 640, rig.height = 400;  // poses and flashes do not depend on the resolution
        auto scene = MakeRigScene(rig);
        auto material = Material::Create(material_name);
        if (!scene.ok() || !material.ok()) {
          std::fprintf(stderr, "%s\n", (scene.ok() ? material.status() : scene.status()).message().c_str());
          return 1;
        }
        BtfEvaluationOptions options;
        options.max_pairs = pairs;
        options.statistical_at_true_mean = true_mean;
        options.btf.colour_space = ParseColourSpace(colour_space).value_or(ColourSpace::kChromaticity);
        options.btf.top_view_prior = top_view_prior;
        options.btf.far_light_falloff_deg = far_light_falloff;
        options.btf.cosine_weighted_lights = cosine;
        options.btf.fit_light_falloff = fit_falloff;
        options.btf.blend_change_from_top = change_from_top;
        options.btf.chromaticity_from_top_view = chroma_from_top;
        options.btf.white_specular_colour = white_specular;
        options.btf.mean_model = mean_model;
        options.btf.mean_model_onset_deg = mean_onset;
        options.btf.max_view_extrapolation = max_view_extrapolation;
        options.btf.view_blend_even_at_pole = even_at_pole;
        int dropped = 0;
        const RigRenderer renderer(*scene, *material);
        std::vector<Eigen::Vector3d> flashes;
        if (!flashes_from.empty()) {
          auto taken = FlashesTaken(flashes_from);
          if (!taken.ok()) {
            std::fprintf(stderr, "%s\n", taken.status().message().c_str());
            return 1;
          }
          flashes = std::move(*taken);
        } else {
          flashes = Flashes(*scene, renderer, std::stoi(shot_count), predict_shadows, objective, spread_cap_deg,
                            board_weights, even_at_pole, guide_images);
        }
        const std::vector<BoardInputs> measured = MeasuredLights(*scene, renderer, flashes);
        for (const BoardInputs& board : measured) {
          if (list_lights) {
            const Eigen::Vector2d v = AnglesDegFromDirection(board.view);
            std::printf("view (%.0f, %.0f), %zu lights:", v.x(), v.y(), board.lights.size());
            for (const auto& l : board.lights) {
              const Eigen::Vector2d a = AnglesDegFromDirection(l);
              std::printf(" (%.0f, %.0f)", a.x(), a.y());
            }
            std::printf("\n");
          }
          if (!LightInterpolator::Create(board.lights).ok()) {  // too few lights to triangulate
            ++dropped;
            continue;
          }
          options.input_views.push_back(board.view);
          options.input_lights_by_view.push_back(board.lights);
        }
        TrueBtfRequest grid;
        grid.size = size;
        grid.samples_per_axis = 2;
        const TrueBtfRenderer true_btf(*material, grid);
        // With --regions 1, each tilted board's input slices show its own part of the material,
        // as on the rig; the top board's and the held-out truth show the top board's part.
        std::vector<std::unique_ptr<TrueBtfRenderer>> regions;
        if (own_regions)
          for (const RigBoard& board : scene->boards) {
            TrueBtfRequest region = grid;
            region.offset_m = board.material_offset_m - scene->boards.front().material_offset_m;
            regions.push_back(std::make_unique<TrueBtfRenderer>(*material, region));
          }
        const TrueSliceFn truth = [&](const Eigen::Vector3d& light, const Eigen::Vector3d& view) {
          for (size_t b = 1; b < regions.size(); ++b)  // board 0 is the top
            if (AngleBetweenDeg(view, measured[b].view) < 0.25) return regions[b]->Render(light, view);
          return true_btf.Render(light, view);
        };
        std::optional<StatisticalBtf> model;
        auto eval = EvaluateStatisticalBtf(truth, options, nullptr, &model);
        if (!eval.ok()) {
          std::printf("%-9s %5s %4s: %s\n", material_name.c_str(), shot_count.c_str(), seed.c_str(),
                      eval.status().message().c_str());
          continue;
        }
        const auto w = eval->Median(&PairScore::wasserstein_pixels);
        auto wins = [&](LightCoverage c) { return 100 * eval->FractionBeatingBoth(&PairScore::wasserstein_pixels, c); };
        std::printf("%-9s %5s %4s %5zu %6d | %5.1f%% %5.1f%% %5.1f%% %5.1f%% | %3d/%3d/%3d | %.5f / %.5f | %3.0f%%\n",
                    material_name.c_str(), shot_count.c_str(), seed.c_str(), options.input_views.size(), eval->input_slices,
                    100 * eval->FractionBeatingBoth(&PairScore::wasserstein_pixels), wins(LightCoverage::kInside),
                    wins(LightCoverage::kNear), wins(LightCoverage::kFar), eval->CountWith(LightCoverage::kInside),
                    eval->CountWith(LightCoverage::kNear), eval->CountWith(LightCoverage::kFar), w[0], w[1],
                    100 * eval->FractionBeatingBoth(&PairScore::wasserstein_chromaticity));
        if (details && model)
          std::printf("   mean model: %s; leave-one-view-out median log error %.4f, top view's %.4f (%d slices)\n",
                      model->mean_model_check().used ? "used" : "not used", model->mean_model_check().model_error,
                      model->mean_model_check().top_view_error, model->mean_model_check().slices);
        if (details && white_specular && model)
          std::printf("   white lobe: strength %.4g, alpha %.3f, body chromaticity (%.3f, %.3f, %.3f)\n",
                      model->white_lobe().strength(), model->white_lobe().alpha(), model->white_lobe().body_chromaticity().x(),
                      model->white_lobe().body_chromaticity().y(), model->white_lobe().body_chromaticity().z());
        if (details) {
          // Colour: the saturation error (median and worst pair) per method.
          const auto median = eval->MedianSaturationError(), worst = eval->WorstSaturationError();
          std::printf("   saturation error, median / worst pair: statistical %.3f / %.3f, top view %.3f / %.3f, "
                      "modulated %.3f / %.3f\n", median[0], worst[0], median[1], worst[1], median[2], worst[2]);
          const PairScore* worst_pair = nullptr;
          for (const PairScore& p : eval->pairs)
            if (!worst_pair || std::abs(p.saturation_ratio[0] - 1) > std::abs(worst_pair->saturation_ratio[0] - 1)) worst_pair = &p;
          if (worst_pair) {
            const Eigen::Vector2d l = AnglesDegFromDirection(worst_pair->light), v = AnglesDegFromDirection(worst_pair->view);
            std::printf("   worst saturation pair: light (%.0f, %.0f), view (%.0f, %.0f), ratio %.3f, %s\n", l.x(), l.y(), v.x(),
                        v.y(), worst_pair->saturation_ratio[0], LightCoverageToString(worst_pair->coverage).c_str());
          }
          // Which baseline the far pairs lose to, and the wins by the view's incidence.
          for (const LightCoverage coverage : {LightCoverage::kInside, LightCoverage::kNear, LightCoverage::kFar}) {
            int lose_top = 0, lose_mod = 0, lose_both = 0, count = 0;
            double ratio_sum = 0;
            for (const PairScore& p : eval->pairs) {
              if (p.coverage != coverage) continue;
              ++count;
              const auto& w = p.wasserstein_pixels;
              lose_top += w[0] >= w[1] && w[0] < w[2];
              lose_mod += w[0] >= w[2] && w[0] < w[1];
              lose_both += w[0] >= w[1] && w[0] >= w[2];
              ratio_sum += std::log(w[0] / std::min(w[1], w[2]));
            }
            std::printf("   %s %d: lose only to top %d, only to modulated %d, to both %d; geo-mean W1 ratio to best baseline %.3f\n",
                        coverage == LightCoverage::kInside ? "inside" : coverage == LightCoverage::kNear ? "near" : "far",
                        count, lose_top, lose_mod, lose_both, std::exp(ratio_sum / std::max(count, 1)));
          }
          for (int theta : {15, 30, 45, 60, 75}) {
            int n = 0, wins = 0, nf = 0, wf = 0;
            for (const PairScore& p : eval->pairs) {
              if (std::abs(AnglesDegFromDirection(p.view).x() - theta) > 1) continue;
              const auto& w = p.wasserstein_pixels;
              const bool win = w[0] < w[1] && w[0] < w[2];
              ++n, wins += win;
              if (p.coverage == LightCoverage::kFar) ++nf, wf += win;
            }
            std::printf("   view theta %d: %d/%d won (far %d/%d)\n", theta, wins, n, wf, nf);
          }
          // Wins by the light's angle to the view's mirror direction: the white specular lobe seen
          // forward, which no view measured (each board sees the flash from the camera's side).
          for (int from = 0; from < 180; from += 30) {
            int n = 0, wins = 0;
            for (const PairScore& p : eval->pairs) {
              const Eigen::Vector3d mirror(-p.view.x(), -p.view.y(), p.view.z());
              const double angle = AngleBetweenDeg(p.light, mirror);
              if (angle < from || angle >= from + 30) continue;
              const auto& w = p.wasserstein_pixels;
              ++n, wins += w[0] < w[1] && w[0] < w[2];
            }
            if (n) std::printf("   light %d-%d deg from the view's mirror direction: %d/%d won\n", from, from + 30, wins, n);
          }
          const auto [unreachable, won] = UnreachableFarPairs(*scene, renderer, flashes, measured, *eval);
          std::printf("   far pairs whose light no flash position (mesocap coverage's candidates) gives the board "
                      "nearest their view: %d, won %d\n", unreachable, won);
        }
        if (!dump_means.empty() && model) DumpMeans(dump_means, material_name, seed, *model, *eval, truth);
        if (!dump_shapes.empty() && model) DumpShapes(dump_shapes, material_name, seed, *model, *eval, truth);
        if (dropped) std::printf("          (%d boards with too few lights to triangulate left out)\n", dropped);
        std::fflush(stdout);
      }
  return 0;
}

}  // namespace
}  // namespace mesocap

int main(int argc, char** argv) { return mesocap::Run(argc, argv); }

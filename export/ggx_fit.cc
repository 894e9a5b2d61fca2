#include "export/ggx_fit.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

#include <ceres/ceres.h>

#include "core/directions.h"
#include "core/image_io.h"
#include "core/median.h"
#include "core/parallel.h"
#include "core/pbr_brdf.h"
#include "core/slice_index.h"
#include "core/text_format.h"

namespace mesocap {

namespace fs = std::filesystem;

std::string GgxFitOptions::Check() const {
  if (max_slices < 8) return "at least 8 slices per texel are needed for a GGX fit";
  if (!(max_theta_deg > 0 && max_theta_deg <= 90)) return "max_theta_deg must lie in (0, 90]";
  if (max_iterations < 1) return "max_iterations must be at least 1";
  return "";
}

Json GgxFitOptions::ToJson() const {
  return {{"max_slices", max_slices}, {"max_theta_deg", max_theta_deg}, {"fit_normals", fit_normals},
          {"max_iterations", max_iterations}};
}

GgxMaterialMaps GgxMaterialMaps::FiguresFromJson(const Json& j) {
  GgxMaterialMaps maps;
  maps.slices_used = JsonInteger(JsonField(j, "", "slices_used"), "slices_used", 0, 1 << 30);
  maps.median_relative_error = JsonNumber(JsonField(j, "", "median_relative_error"), "median_relative_error", 0, 1e9);
  maps.seconds = JsonNumber(JsonField(j, "", "seconds"), "seconds", 0, 1e9);
  maps.mean_iterations = JsonNumber(JsonField(j, "", "mean_iterations"), "mean_iterations", 0, 1e9);
  maps.mean_evaluations = JsonNumber(JsonField(j, "", "mean_evaluations"), "mean_evaluations", 0, 1e9);
  return maps;
}

Json GgxMaterialMaps::ToJson() const {
  return {{"width", base_color.width()}, {"height", base_color.height()}, {"slices_used", slices_used},
          {"median_relative_error", median_relative_error}, {"seconds", seconds},
          {"mean_iterations", mean_iterations}, {"mean_evaluations", mean_evaluations}};
}

namespace {

// Bounds of the parameters (a roughness of 0 is a mirror the slices cannot resolve).
constexpr double kMinRoughness = 0.05, kMaxSlope = 3.0;

using Observation = PbrGeometry;

template <typename T>
Eigen::Matrix<T, 3, 1> NormalFromSlope(const T* slope) {
  return Eigen::Matrix<T, 3, 1>(-slope[0], -slope[1], T(1)).normalized();
}

// The least-squares base colour of one texel from the model's affine terms per observation
// (core/pbr_brdf.h), clamped to [0, 1], and the residuals it leaves (model minus observed, per
// observation and channel) when `residuals` is given.
template <typename T>
Eigen::Matrix<T, 3, 1> ProjectBaseColorWith(const std::vector<PbrAffine<T>>& terms, const float* values, T* residuals) {
  T aa(0);
  Eigen::Matrix<T, 3, 1> ay = Eigen::Matrix<T, 3, 1>::Zero();
  for (size_t k = 0; k < terms.size(); ++k) {
    aa += terms[k].a * terms[k].a;
    for (int c = 0; c < 3; ++c) ay[c] += terms[k].a * (T(values[3 * k + c]) - terms[k].b);
  }
  Eigen::Matrix<T, 3, 1> base = Eigen::Matrix<T, 3, 1>::Zero();
  if (aa > T(0))
    for (int c = 0; c < 3; ++c) {
      base[c] = ay[c] / aa;
      if (base[c] < T(0)) base[c] = T(0);
      if (base[c] > T(1)) base[c] = T(1);
    }
  if (residuals)
    for (size_t k = 0; k < terms.size(); ++k)
      for (int c = 0; c < 3; ++c) residuals[3 * k + c] = terms[k].a * base[c] + terms[k].b - T(values[3 * k + c]);
  return base;
}

template <typename T>
void AffineTermsOf(const std::vector<Observation>& dirs, const T& roughness, const T& metallic,
                   const Eigen::Matrix<T, 3, 1>& n, std::vector<PbrAffine<T>>* terms) {
  terms->resize(dirs.size());
  for (size_t k = 0; k < dirs.size(); ++k) (*terms)[k] = PbrAffineTerms(roughness, metallic, n, dirs[k]);
}

// The same for given roughness, metallic and normal.
template <typename T>
__attribute__((flatten)) Eigen::Matrix<T, 3, 1> ProjectBaseColor(const std::vector<Observation>& dirs, const float* values, const T& roughness,
                                        const T& metallic, const Eigen::Matrix<T, 3, 1>& n, T* residuals) {
  thread_local std::vector<PbrAffine<T>> terms;
  AffineTermsOf(dirs, roughness, metallic, n, &terms);
  return ProjectBaseColorWith(terms, values, residuals);
}

// Residuals of one texel over roughness, metallic and the normal's slope, the base colour
// projected out (variable projection: 4 parameters instead of 7, and better conditioned).
struct TexelCost {
  const std::vector<Observation>* directions;
  const float* values;  // directions->size() x 3

  template <typename T>
  bool operator()(const T* roughness, const T* metallic, const T* slope, T* residuals) const {
    ProjectBaseColor(*directions, values, roughness[0], metallic[0], NormalFromSlope(slope), residuals);
    return true;
  }
};

// The squared error left with the best base colour for these terms.
double SquaredErrorWith(const std::vector<PbrAffine<double>>& terms, const float* values) {
  thread_local std::vector<double> residuals;
  residuals.resize(3 * terms.size());
  ProjectBaseColorWith(terms, values, residuals.data());
  double sq = 0;
  for (double r : residuals) sq += r * r;
  return sq;
}

// The same for given roughness, metallic and normal slope.
double SquaredError(const std::vector<Observation>& dirs, const float* values, double roughness, double metallic,
                    const double* slope) {
  thread_local std::vector<PbrAffine<double>> terms;
  AffineTermsOf<double>(dirs, roughness, metallic, NormalFromSlope(slope), &terms);
  return SquaredErrorWith(terms, values);
}

// The starts every texel tries: a coarse grid over roughness and metallic with the patch's
// normal. Their terms depend on the directions alone, so they are made once for all texels.
struct StartGrid {
  struct Point {
    double roughness, metallic;
    std::vector<PbrAffine<double>> terms;
  };
  std::vector<Point> points;

  explicit StartGrid(const std::vector<Observation>& dirs) {
    const double flat[2] = {0, 0};
    for (double r : {0.15, 0.3, 0.5, 0.75, 1.0})
      for (double m : {0.0, 0.5, 1.0}) {
        Point& p = points.emplace_back(Point{r, m, {}});
        AffineTermsOf<double>(dirs, r, m, NormalFromSlope(flat), &p.terms);
      }
  }
};

struct TexelFit {
  Eigen::Vector3d base, normal;
  double slope[2] = {0, 0};
  double roughness = 0.5, metallic = 0, relative_error = 0;
  int iterations = 0, evaluations = 0;
};

// `previous`: the fit of the texel before in the row, a start that is often close.
TexelFit FitTexel(const std::vector<Observation>& dirs, const float* values, const GgxFitOptions& options,
                  const StartGrid& grid, const TexelFit* previous) {
  // Start: the best of the grid and the previous texel's parameters.
  double best = 1e300;
  double roughness = 0.5, metallic = 0, slope[2] = {0, 0};
  for (const StartGrid::Point& p : grid.points) {
    const double sq = SquaredErrorWith(p.terms, values);
    if (sq < best) best = sq, roughness = p.roughness, metallic = p.metallic;
  }
  if (previous && SquaredError(dirs, values, previous->roughness, previous->metallic, previous->slope) < best)
    roughness = previous->roughness, metallic = previous->metallic, slope[0] = previous->slope[0], slope[1] = previous->slope[1];

  ceres::Problem problem;
  auto* cost = new ceres::AutoDiffCostFunction<TexelCost, ceres::DYNAMIC, 1, 1, 2>(new TexelCost{&dirs, values},
                                                                                   int(3 * dirs.size()));
  problem.AddResidualBlock(cost, nullptr, &roughness, &metallic, slope);
  problem.SetParameterLowerBound(&roughness, 0, kMinRoughness);
  problem.SetParameterUpperBound(&roughness, 0, 1.0);
  problem.SetParameterLowerBound(&metallic, 0, 0.0);
  problem.SetParameterUpperBound(&metallic, 0, 1.0);
  for (int k = 0; k < 2; ++k) {
    problem.SetParameterLowerBound(slope, k, -kMaxSlope);
    problem.SetParameterUpperBound(slope, k, kMaxSlope);
  }
  if (!options.fit_normals) problem.SetParameterBlockConstant(slope);
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  solver.max_num_iterations = options.max_iterations;
  solver.num_threads = 1;  // texels run in parallel
  solver.logging_type = ceres::SILENT;
  // Steps far below an 8-bit texture's 1/255 are not worth iterating for.
  solver.parameter_tolerance = 1e-4;
  solver.function_tolerance = 1e-6;
  // No projected line search after each step: Ceres's own note calls it "not terribly effective"
  // (ceres-solver#187), and here it cost about five Jacobians an iteration (the demo's fit:
  // 10 s -> 3.4 s, same median error). Steps stay inside the bounds: Ceres projects each onto them.
  solver.max_num_line_search_step_size_iterations = 0;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);

  TexelFit fit;
  fit.roughness = roughness;
  fit.metallic = metallic;
  fit.slope[0] = slope[0], fit.slope[1] = slope[1];
  fit.normal = NormalFromSlope(slope);
  fit.base = ProjectBaseColor<double>(dirs, values, roughness, metallic, fit.normal, nullptr);
  fit.iterations = int(summary.iterations.size());
  fit.evaluations = summary.num_residual_evaluations;
  double signal = 0;
  for (size_t k = 0; k < 3 * dirs.size(); ++k) signal += double(values[k]) * values[k];
  fit.relative_error = signal > 0 ? std::sqrt(SquaredError(dirs, values, roughness, metallic, slope) / signal) : 0;
  return fit;
}

}  // namespace

Image RelightPbrMaterial(const GgxMaterialMaps& maps, const Eigen::Vector3d& light, const Eigen::Vector3d& view) {
  const PbrGeometry geometry(light, view);
  Image out(maps.base_color.width(), maps.base_color.height(), 3);
  for (int y = 0; y < out.height(); ++y)
    for (int x = 0; x < out.width(); ++x) {
      const Eigen::Vector3d base(maps.base_color.at(x, y, 0), maps.base_color.at(x, y, 1), maps.base_color.at(x, y, 2));
      const Eigen::Vector3d n(maps.normal.at(x, y, 0), maps.normal.at(x, y, 1), maps.normal.at(x, y, 2));
      const Eigen::Vector3d f = PbrReflectance<double>(base, maps.roughness.at(x, y, 0), maps.metallic.at(x, y, 0), n, geometry);
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = float(f[c]);
    }
  return out;
}

StatusOr<GgxMaterialMaps> FitGgxMaterial(const fs::path& index_json, const GgxFitOptions& options, int board,
                                         const ProgressFn& progress) {
  return FitGgxMaterialRows(index_json, options, RowBand{}, board, progress);
}

StatusOr<GgxObservations> ReadGgxObservations(const fs::path& index_json, const GgxFitOptions& options, RowBand rows,
                                              int board, const ProgressFn& progress) {
  if (std::string why = options.Check(); !why.empty()) return Status::Error(why);
  auto index = ReadSliceIndex(index_json);
  if (!index.ok()) return index.status();
  std::vector<const SliceIndexEntry*> usable;
  const double cos_max = std::cos(DegToRad(options.max_theta_deg));
  for (const SliceIndexEntry& e : index->slices) {
    if (board < 0) board = e.board;
    if (e.board == board && e.light.z() >= cos_max && e.view.z() >= cos_max) usable.push_back(&e);
  }
  if (usable.size() < 8)
    return Status::Error(index_json.string() + Format(": %zu slices within %.0f deg of the normal; a GGX fit needs 8",
                                                      usable.size(), options.max_theta_deg));
  std::vector<const SliceIndexEntry*> chosen;
  const size_t n = std::min(usable.size(), size_t(options.max_slices));
  for (size_t k = 0; k < n; ++k) chosen.push_back(usable[k * usable.size() / n]);

  auto first = ReadImageInfo(chosen.front()->file);  // the size; the slices are read below
  if (!first.ok()) return first.status();
  if (rows.last < 0) rows.last = first->height;
  if (rows.first < 0 || rows.first > rows.last || rows.last > first->height)
    return Status::Error(Format("%s: rows %d..%d are not within its %d rows", index_json.string().c_str(), rows.first,
                                rows.last, first->height));
  GgxObservations out;
  out.width = first->width;
  out.height = rows.last - rows.first;  // the band's rows
  for (const SliceIndexEntry* e : chosen) out.lights.push_back(e->light), out.views.push_back(e->view);
  const size_t texels = size_t(out.width) * out.height, skipped_texels = size_t(out.width) * rows.first;
  out.table.resize(texels * n * 3);
  std::vector<std::string> errors(n);
  std::atomic<int> read = 0;
  std::atomic<bool> cancelled = false;
  ParallelFor(0, int(n), [&](int k) {
    if (cancelled) return;
    auto slice = ReadImage(chosen[k]->file);
    if (!slice.ok()) return void(errors[k] = slice.status().message());
    if (slice->width() != out.width || slice->height() != first->height || slice->channels() < 3)
      return void(errors[k] = chosen[k]->file.string() + ": not the size or channels of the other slices");
    const float* band = slice->data() + skipped_texels * slice->channels();
    for (size_t t = 0; t < texels; ++t)
      for (int c = 0; c < 3; ++c) out.table[(t * n + k) * 3 + c] = band[t * slice->channels() + c];
    if (!ReportProgress(progress, ++read, int(n), "reading slices")) cancelled = true;
  }, options.num_threads);
  if (cancelled) return Status::Cancelled();
  for (const std::string& e : errors)
    if (!e.empty()) return Status::Error(e);
  return out;
}

StatusOr<GgxMaterialMaps> FitGgxObservations(const GgxObservations& observations, const GgxFitOptions& options,
                                             const ProgressFn& progress) {
  if (std::string why = options.Check(); !why.empty()) return Status::Error(why);
  const auto start = std::chrono::steady_clock::now();
  const int width = observations.width, height = observations.height;
  const size_t n = observations.lights.size(), texels = size_t(width) * height;
  if (observations.table.size() != texels * n * 3) return Status::Error("GGX fit: the observations do not fill their table");
  std::vector<Observation> dirs;
  for (size_t k = 0; k < n; ++k) dirs.emplace_back(observations.lights[k], observations.views[k]);
  const std::vector<float>& table = observations.table;
  GgxMaterialMaps maps;
  maps.base_color = Image(width, height, 3);
  maps.roughness = Image(width, height, 1);
  maps.metallic = Image(width, height, 1);
  maps.normal = Image(width, height, 3);
  maps.relative_error = Image(width, height, 1);
  const StartGrid grid(dirs);
  std::atomic<int> rows_done = 0;
  std::atomic<long> iterations = 0, evaluations = 0;
  std::atomic<bool> cancelled = false;
  ParallelFor(0, height, [&](int y) {
    if (cancelled) return;
    TexelFit fit;
    for (int x = 0; x < width; ++x) {
      const size_t t = size_t(y) * width + x;
      fit = FitTexel(dirs, &table[t * n * 3], options, grid, x > 0 ? &fit : nullptr);
      for (int c = 0; c < 3; ++c) {
        maps.base_color.at(x, y, c) = float(fit.base[c]);
        maps.normal.at(x, y, c) = float(fit.normal[c]);
      }
      maps.roughness.at(x, y, 0) = float(fit.roughness);
      maps.metallic.at(x, y, 0) = float(fit.metallic);
      maps.relative_error.at(x, y, 0) = float(fit.relative_error);
      iterations += fit.iterations;
      evaluations += fit.evaluations;
    }
    if (!ReportProgress(progress, ++rows_done, height, "fitting")) cancelled = true;
  }, options.num_threads);
  if (cancelled) return Status::Cancelled();
  maps.slices_used = int(n);
  if (texels > 0) {  // a band may hold no rows (more shards than rows)
    maps.median_relative_error =
        UpperMedian(std::vector<float>(maps.relative_error.data(), maps.relative_error.data() + texels));
    maps.mean_iterations = double(iterations) / texels;
    maps.mean_evaluations = double(evaluations) / texels;
  }
  maps.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return maps;
}

StatusOr<GgxMaterialMaps> FitGgxMaterialRows(const fs::path& index_json, const GgxFitOptions& options, RowBand rows,
                                             int board, const ProgressFn& progress) {
  const auto start = std::chrono::steady_clock::now();
  auto observations = ReadGgxObservations(index_json, options, rows, board, progress);
  if (!observations.ok()) return observations.status();
  auto maps = FitGgxObservations(*observations, options, progress);
  if (maps.ok()) maps->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return maps;
}

}  // namespace mesocap

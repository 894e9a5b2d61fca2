#include "synth/kmeans.h"

#include <algorithm>
#include <limits>
#include <random>

#include "core/cancel.h"
#include "core/parallel.h"
#include "core/status.h"

namespace mesocap {
namespace {

constexpr Eigen::Index kRowsPerJob = 1024;

// Points one per row, stored row by row: the loops over points read each one contiguously (a
// column-major row is strided by the point count: a cache miss per coordinate).
using PointRows = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// k-means++ (Arthur & Vassilvitskii): each next centre drawn with probability proportional to the
// squared distance to the nearest centre so far.
Eigen::MatrixXd PlusPlusStart(const PointRows& points, int clusters, uint32_t seed, int num_threads) {
  const Eigen::Index n = points.rows();
  std::mt19937_64 rng(seed);
  Eigen::MatrixXd centres(clusters, points.cols());
  centres.row(0) = points.row(Eigen::Index(rng() % uint64_t(n)));
  std::vector<double> nearest(n, std::numeric_limits<double>::infinity());
  const int jobs = int((n + kRowsPerJob - 1) / kRowsPerJob);
  auto update = [&](int c) {  // each point on its own: the same result for any thread count
    ParallelFor(0, jobs, [&](int job) {
      for (Eigen::Index i = job * kRowsPerJob; i < std::min(n, (job + 1) * kRowsPerJob); ++i)
        nearest[i] = std::min(nearest[i], (points.row(i) - centres.row(c)).squaredNorm());
    }, num_threads);
  };
  update(0);
  for (int c = 1; c < clusters; ++c) {
    if (CancelRequested()) {  // Ctrl-C: the caller discards the result at its next progress check
      for (; c < clusters; ++c) centres.row(c) = centres.row(0);
      break;
    }
    double total = 0;
    for (double d : nearest) total += d;
    Eigen::Index pick = Eigen::Index(rng() % uint64_t(n));
    if (total > 0) {
      double target = std::uniform_real_distribution<double>(0, total)(rng);
      for (pick = 0; pick < n - 1 && (target -= nearest[pick]) > 0; ++pick) {
      }
    }
    centres.row(c) = points.row(pick);
    update(c);
  }
  return centres;
}

}  // namespace

std::vector<int> NearestCentres(const Eigen::MatrixXd& points, const Eigen::MatrixXd& centres, int num_threads,
                                std::vector<double>* squared_distances) {
  const Eigen::Index n = points.rows();
  std::vector<int> labels(n, 0);
  if (squared_distances) squared_distances->assign(n, 0.0);
  const Eigen::VectorXd centre_norms = centres.rowwise().squaredNorm();
  const Eigen::VectorXd point_norms = squared_distances ? Eigen::VectorXd(points.rowwise().squaredNorm()) : Eigen::VectorXd();
  const int jobs = int((n + kRowsPerJob - 1) / kRowsPerJob);
  ParallelFor(0, jobs, [&](int job) {
    const Eigen::Index begin = job * kRowsPerJob, rows = std::min(kRowsPerJob, n - begin);
    const Eigen::MatrixXd dots = points.middleRows(begin, rows) * centres.transpose();
    for (Eigen::Index r = 0; r < rows; ++r) {
      double best = std::numeric_limits<double>::infinity();
      int best_c = 0;
      for (Eigen::Index c = 0; c < centres.rows(); ++c) {
        const double d = centre_norms(c) - 2 * dots(r, c);
        if (d < best) best = d, best_c = int(c);
      }
      labels[begin + r] = best_c;
      if (squared_distances) (*squared_distances)[begin + r] = std::max(0.0, best + point_norms(begin + r));
    }
  }, num_threads);
  return labels;
}

KMeansResult KMeans(const Eigen::MatrixXd& points, const KMeansOptions& options) {
  MESOCAP_CHECK(points.rows() > 0 && options.clusters > 0, "k-means of no points or into no clusters");
  const Eigen::Index n = points.rows();
  const int clusters = int(std::min<Eigen::Index>(options.clusters, n));
  KMeansResult result;
  const PointRows rows = points;
  result.centres = PlusPlusStart(rows, clusters, options.seed, options.num_threads);
  std::vector<double> distances;
  result.labels = NearestCentres(points, result.centres, options.num_threads, &distances);
  for (result.iterations = 1; result.iterations <= options.max_iterations && !CancelRequested(); ++result.iterations) {
    Eigen::MatrixXd sums = Eigen::MatrixXd::Zero(clusters, points.cols());
    std::vector<Eigen::Index> counts(clusters, 0);
    for (Eigen::Index i = 0; i < n; ++i) sums.row(result.labels[i]) += rows.row(i), ++counts[result.labels[i]];
    for (int c = 0; c < clusters; ++c) {
      if (counts[c] > 0) {
        result.centres.row(c) = sums.row(c) / double(counts[c]);
        continue;
      }
      // An empty cluster takes the point that is worst served (and that point leaves its old one).
      const Eigen::Index far = std::max_element(distances.begin(), distances.end()) - distances.begin();
      result.centres.row(c) = rows.row(far);
      distances[far] = 0;
    }
    std::vector<int> labels = NearestCentres(points, result.centres, options.num_threads, &distances);
    Eigen::Index changed = 0;
    for (Eigen::Index i = 0; i < n; ++i) changed += labels[i] != result.labels[i];
    result.labels = std::move(labels);
    if (changed == 0 || double(changed) < options.min_changed * double(n)) {
      result.converged = true;
      break;
    }
  }
  result.iterations = std::min(result.iterations, options.max_iterations);
  return result;
}

}  // namespace mesocap

// K-means clustering (Lloyd's iterations from a k-means++ start), the clustering behind 3D
// textons (Leung & Malik 2001; Tong et al. 2002 §4): the representative slices and the textons.
// Deterministic for a seed, whatever the thread count.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace mesocap {

struct KMeansOptions {
  int clusters = 400;
  int max_iterations = 30;  // Lloyd iterations
  uint32_t seed = 1;
  int num_threads = -1;
  // Stops once an iteration changes fewer than this share of the labels (0: only when none
  // changes). The last step is always an assignment, so labels are each point's nearest centre.
  double min_changed = 0.001;
};

struct KMeansResult {
  Eigen::MatrixXd centres;  // clusters x dimensions: the mean of each cluster's points
  // Per point, its nearest centre (the final step is an assignment, so relabelling the points
  // with `centres` gives these labels back).
  std::vector<int> labels;
  int iterations = 0;
  bool converged = false;  // stopped by min_changed, not by max_iterations
};

// `points` holds one point per row. Clusters are capped at the number of points; a cluster left
// empty is moved to the point farthest from its centre. Ctrl-C (core/cancel.h) ends it early with
// a partial result, which callers discard at their next progress check.
KMeansResult KMeans(const Eigen::MatrixXd& points, const KMeansOptions& options);

// Nearest centre of every point (lowest index on ties), by ||x||^2 + ||c||^2 - 2 x.c.
std::vector<int> NearestCentres(const Eigen::MatrixXd& points, const Eigen::MatrixXd& centres, int num_threads = -1,
                                std::vector<double>* squared_distances = nullptr);

}  // namespace mesocap

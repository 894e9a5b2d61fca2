// Where a BTF slice between measured directions borrows from (Ngan & Durand section 3.2).
//  - Light directions: projected on the unit disk (x, y of the unit vector), Delaunay-
//    triangulated; a query takes the barycentric weights of its triangle, and a query outside
//    the hull is first moved radially onto the hull.
//  - View directions: grouped into rings of similar incidence (top, ~30, ~60 deg); each ring is a
//    closed polyline in azimuth; a query interpolates along the two rings that bracket its
//    incidence, then linearly in incidence (or, from a top view, in 1 - cos) between them,
//    extrapolating (negative weights) above the outermost ring or below the innermost.
// Weights always sum to one.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/status.h"

namespace mesocap {

struct WeightedIndex {
  int index = 0;
  double weight = 0;
};

// Delaunay triangulation of 2-D points (reconstruct/delaunay.cc, CGAL with exact predicates);
// each triangle's vertices counter-clockwise, smallest index first, triangles sorted. Exactly
// co-circular points get one of their valid triangulations, always the same one; collinear
// points give none, and slivers with an area below 1e-12 of the squared extent are left out.
std::vector<std::array<int, 3>> DelaunayTriangulation(const std::vector<Eigen::Vector2d>& points);

class LightInterpolator {
 public:
  // Fails (message says why) on fewer than 3 directions, duplicates closer than
  // `min_separation_deg`, or all directions on one great circle through the normal (collinear
  // on the disk): no triangle to blend in.
  static StatusOr<LightInterpolator> Create(const std::vector<Eigen::Vector3d>& directions,
                                            double min_separation_deg = 0.25);
  // Up to three measured directions and their barycentric weights (non-negative).
  std::vector<WeightedIndex> Weights(const Eigen::Vector3d& direction) const;
  // True when `direction` falls inside the triangulated hull (no radial projection needed).
  bool Contains(const Eigen::Vector3d& direction) const;
  const std::vector<std::array<int, 3>>& triangles() const { return triangles_; }

 private:
  std::vector<Eigen::Vector2d> disk_;
  std::vector<std::array<int, 3>> triangles_;
  std::vector<std::array<int, 2>> hull_edges_;
};

class ViewInterpolator {
 public:
  // Rings are formed by sorting incidences and starting a new ring at a gap above `ring_gap_deg`.
  // Beyond the outermost (or innermost) ring, extrapolation goes at most `max_extrapolation`
  // ring spacings further (larger infinite: the paper's plain linear extrapolation; 0: hold
  // the outer ring's statistics).
  // `even_at_pole`: between a top view (incidence under 5 deg) and the first ring, interpolate
  // in 1 - cos(theta) instead of theta. A texture that looks alike from opposite azimuths has
  // statistics even in theta through the pole, so near it they change as theta^2 ~ 2 (1 - cos
  // theta), not linearly: at 15 deg the 30 deg ring weighs 0.254, not 0.5. false: the paper's.
  static StatusOr<ViewInterpolator> Create(const std::vector<Eigen::Vector3d>& directions,
                                           double ring_gap_deg = 10.0, double max_extrapolation = 1e9,
                                           bool even_at_pole = false);
  std::vector<WeightedIndex> Weights(const Eigen::Vector3d& direction) const;
  int ring_count() const { return static_cast<int>(rings_.size()); }

 private:
  struct Ring {
    std::vector<int> views;         // sorted by azimuth
    std::vector<double> phi_deg, theta_deg;
    double mean_theta_deg = 0;
  };
  // Views on `ring` around azimuth phi, with weights, and the ring's incidence there.
  std::vector<WeightedIndex> AlongRing(const Ring& ring, double phi_deg, double* theta_deg) const;
  std::vector<Ring> rings_;
  double max_extrapolation_ = 1e9;
  bool even_at_pole_ = false;
};

// Adds equal indices together and drops zero weights.
std::vector<WeightedIndex> MergeWeights(std::vector<WeightedIndex> weights);

}  // namespace mesocap

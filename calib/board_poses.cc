#include "calib/board_poses.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <opencv2/calib3d.hpp>

#include <cmath>
#include <map>

#include "calib/projection.h"
#include "core/directions.h"
#include "core/parallel.h"

namespace mesocap {
namespace {

struct CornerObservation {
  Eigen::Vector2d board_xy;  // board frame, metres
  Eigen::Vector2d pixel;
  int shot;
};

// Residual of one tag corner: observed pixel minus the projection of the board point.
struct BoardCornerCost {
  BoardCornerCost(const Eigen::Vector2d& xy, const Eigen::Vector2d& px, const double* intrinsics)
      : xy_(xy), px_(px), intrinsics_(intrinsics) {}
  template <typename T>
  bool operator()(const T* rotation, const T* translation, T* residual) const {
    const T p_board[3] = {T(xy_.x()), T(xy_.y()), T(0)};
    T p_cam[3];
    ceres::AngleAxisRotatePoint(rotation, p_board, p_cam);
    for (int i = 0; i < 3; ++i) p_cam[i] += translation[i];
    T k[9];
    for (int i = 0; i < 9; ++i) k[i] = T(intrinsics_[i]);
    T uv[2];
    ProjectWithDistortion(k, p_cam, uv);
    residual[0] = uv[0] - T(px_.x());
    residual[1] = uv[1] - T(px_.y());
    return true;
  }
  Eigen::Vector2d xy_, px_;
  const double* intrinsics_;
};

}  // namespace

Json BoardPose::ToJson() const {
  Json j = {{"id", id}, {"found", found}};
  if (!found) {
    j["why_not"] = why_not;
    return j;
  }
  j["R"] = mesocap::ToJson(R);
  j["t"] = mesocap::ToJson(t);
  j["corners_used"] = corners_used;
  j["shots_seen"] = shots_seen;
  j["rms_reprojection_px"] = rms_reprojection_px;
  j["rotation_stddev_deg"] = rotation_stddev_deg;
  j["translation_stddev_mm"] = translation_stddev_mm;
  return j;
}

std::vector<BoardPose> EstimateBoardPoses(const CameraModel& camera, const std::vector<LayoutBoard>& boards,
                                          const std::vector<std::vector<TagDetection>>& detections,
                                          const BoardPoseOptions& options) {
  const double intrinsics[9] = {camera.K(0, 0), camera.K(1, 1), camera.K(0, 2), camera.K(1, 2), camera.dist[0],
                                camera.dist[1], camera.dist[2], camera.dist[3], camera.dist[4]};
  cv::Mat K = (cv::Mat_<double>(3, 3) << camera.K(0, 0), 0, camera.K(0, 2), 0, camera.K(1, 1), camera.K(1, 2), 0, 0, 1);
  cv::Mat dist = (cv::Mat_<double>(1, 5) << camera.dist[0], camera.dist[1], camera.dist[2], camera.dist[3], camera.dist[4]);

  std::vector<BoardPose> poses(boards.size());
  ParallelFor(0, int(boards.size()), [&](int b) {
    const LayoutBoard& board = boards[b];
    BoardPose& pose = poses[b];
    pose.id = board.id;
    std::map<int, const LayoutTag*> tag_by_id;
    for (const auto& t : board.tags) tag_by_id[t.id] = &t;
    std::vector<CornerObservation> obs;
    std::map<int, int> per_shot;
    for (size_t s = 0; s < detections.size(); ++s)
      for (const TagDetection& d : detections[s]) {
        auto it = tag_by_id.find(d.id);
        if (it == tag_by_id.end()) continue;
        for (int c = 0; c < 4; ++c) obs.push_back({it->second->corners_m[c], d.corners_px[c], int(s)});
        per_shot[int(s)] += 4;
      }
    // A hand-marked outline (a negative pseudo-tag id, calib/marked_corners.h) spans the whole
    // board: its four corners alone fix the pose better than two small tags.
    bool outline = false;
    for (const auto& detections_of_shot : detections)
      for (const TagDetection& d : detections_of_shot) outline |= d.id < 0 && tag_by_id.count(d.id);
    if (int(obs.size()) < (outline ? 4 : options.min_corners)) {
      pose.why_not = obs.empty() ? "no tag of this board was detected in any shot (hidden or unlit)"
                                 : "too few tag corners detected (" + std::to_string(obs.size()) + ")";
      return;
    }
    // Initial pose: planar PnP on the shot that sees most of the board.
    int best_shot = per_shot.begin()->first;
    for (const auto& [s, n] : per_shot)
      if (n > per_shot[best_shot]) best_shot = s;
    std::vector<cv::Point3d> object;
    std::vector<cv::Point2d> image;
    for (const auto& o : obs)
      if (o.shot == best_shot) {
        object.emplace_back(o.board_xy.x(), o.board_xy.y(), 0);
        image.emplace_back(o.pixel.x(), o.pixel.y());
      }
    cv::Vec3d rvec, tvec;
    cv::solvePnP(object, image, K, dist, rvec, tvec, false, object.size() >= 4 ? cv::SOLVEPNP_IPPE : cv::SOLVEPNP_ITERATIVE);
    double rotation[3] = {rvec[0], rvec[1], rvec[2]}, translation[3] = {tvec[0], tvec[1], tvec[2]};

    ceres::Problem problem;
    for (const auto& o : obs)
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<BoardCornerCost, 2, 3, 3>(
                                   new BoardCornerCost(o.board_xy, o.pixel, intrinsics)),
                               new ceres::HuberLoss(options.huber_px), rotation, translation);
    ceres::Solver::Options solver;
    solver.linear_solver_type = ceres::DENSE_QR;
    solver.max_num_iterations = 100;
    solver.num_threads = 1;
    ceres::Solver::Summary summary;
    ceres::Solve(solver, &problem, &summary);

    double sq = 0;
    ceres::Problem::EvaluateOptions eval;
    std::vector<double> residuals;
    problem.Evaluate(eval, nullptr, &residuals, nullptr, nullptr);
    for (double r : residuals) sq += r * r;
    pose.rms_reprojection_px = std::sqrt(sq / obs.size());
    ceres::Covariance::Options cov_options;
    ceres::Covariance covariance(cov_options);
    std::vector<std::pair<const double*, const double*>> blocks = {{rotation, rotation}, {translation, translation}};
    if (covariance.Compute(blocks, &problem)) {
      // Scale the unit-weight covariance by the residual variance.
      const double sigma2 = sq / std::max<size_t>(1, residuals.size() - 6);
      double cr[9], ct[9];
      covariance.GetCovarianceBlock(rotation, rotation, cr);
      covariance.GetCovarianceBlock(translation, translation, ct);
      pose.rotation_stddev_deg = RadToDeg(std::sqrt(sigma2 * (cr[0] + cr[4] + cr[8])));
      pose.translation_stddev_mm = 1000 * std::sqrt(sigma2 * (ct[0] + ct[4] + ct[8]));
    }
    double R[9];
    ceres::AngleAxisToRotationMatrix(rotation, R);  // column-major
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) pose.R(r, c) = R[c * 3 + r];
    pose.t = {translation[0], translation[1], translation[2]};
    pose.found = summary.IsSolutionUsable();
    if (!pose.found) pose.why_not = "pose refinement failed: " + summary.message;
    pose.corners_used = int(obs.size());
    pose.shots_seen = int(per_shot.size());
  });
  return poses;
}

}  // namespace mesocap

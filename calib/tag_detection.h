// AprilTag (tag36h11) detection with libapriltag, on linear intensities and in OpenCV's pixel
// convention (libapriltag's corners are shifted by -0.5 px to put pixel centres on integers).
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/image.h"

namespace mesocap {

struct TagDetection {
  int id = 0;
  std::array<Eigen::Vector2d, 4> corners_px;  // libapriltag's order, OpenCV pixel convention
  float decision_margin = 0;                  // contrast of the decoded bits (8-bit levels)
};

struct TagDetectOptions {
  float quad_sigma = 0.8f;        // blur before segmentation: steadier edge fits on small tags
  float min_decision_margin = 10;  // below this a tag is too dimly lit to measure
};

// Detects tags in a linear RGB (or grey) image. Thread-safe: one detector per call.
std::vector<TagDetection> DetectTags(const Image& linear, const TagDetectOptions& options = {});

}  // namespace mesocap

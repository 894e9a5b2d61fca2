// Directional lights from one reflective sphere (classic RTI capture: camera and sphere fixed,
// only the light moves, the camera far enough for an orthographic view). The sphere's circle
// comes from a mask image or is given; in each photo the mirror highlight's centroid gives the
// normal n there, and the light is the view direction mirrored about it: L = 2 (n.v) n - v.
// Directions are in RTI's frame (x toward the image's right, y toward its top, z toward the
// camera), as .lp files hold them (export/lp_file.h).
#pragma once

#include <string>

#include <Eigen/Core>

#include "core/image.h"
#include "core/json.h"
#include "core/status.h"

namespace mesocap {

// Pixel coordinates: OpenCV's, the centre of the top-left pixel at (0, 0).
struct SphereCircle {
  Eigen::Vector2d centre_px{0, 0};
  double radius_px = 0;
  Json ToJson() const;
};

struct SphereLightsOptions {
  double saturation = 0.98;         // linear value from which a pixel counts as clipped
  double blob_level = 0.5;          // highlight: pixels above median + blob_level * (peak - median)
  double min_peak_over_median = 2;  // the brightest point on the sphere must stand out this much
  double max_blob_radius = 0.15;    // of the sphere's radius: a larger bright area is no highlight
  double max_rim_radius = 0.97;     // of the sphere's radius: a highlight further out is too
                                    // grazing to trust (the light is almost behind the sphere)
  std::string Check() const;        // empty when valid
};

struct SphereLight {
  bool found = false;
  std::string why_not;                             // when not found
  Eigen::Vector2d highlight_px{0, 0};              // centroid of the highlight blob
  int blob_pixels = 0;
  bool saturated = false;                          // the blob is clipped (centroid of the plateau)
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();     // at the highlight, RTI frame
  Eigen::Vector3d light_dir = Eigen::Vector3d::Zero();  // unit, RTI frame
  Json ToJson() const;
};

// The circle of a sphere mask (white = sphere; grey edge pixels count as partial coverage):
// area and centroid (image moments), sub-pixel for an anti-aliased mask. Fails when the mask is
// empty, touches the image border, or is not round (area against its extent).
StatusOr<SphereCircle> CircleFromMask(const Image& mask);

// Finds the highlight on the sphere in one photo (linear values) and its light direction.
SphereLight FindSphereLight(const Image& photo, const SphereCircle& sphere, const SphereLightsOptions& options = {});

// Light direction for a highlight at `highlight_px` on `sphere`, orthographic view (0, 0, 1).
Eigen::Vector3d LightFromHighlight(const SphereCircle& sphere, const Eigen::Vector2d& highlight_px,
                                   Eigen::Vector3d* normal = nullptr);

}  // namespace mesocap

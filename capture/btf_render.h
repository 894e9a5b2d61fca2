// The material model's light transport, shared by the true-BTF renderer and the shot renderer
// so that a rendered photograph and the ground-truth slice agree by construction.
// Frame: the material plane, z = surface normal of the backing board; the reference plane is
// z = 0 (the board surface) and heights are >= 0 above it.
#pragma once

#include <Eigen/Core>

#include "capture/rig_material.h"
#include "core/image.h"

namespace mesocap {

struct MaterialHit {
  Eigen::Vector3d point;   // on the height field, material frame, metres
  Eigen::Vector3f normal;  // unit
  Eigen::Vector3f albedo;
};

// The surface point a viewer looking back along `wo` (unit, wo.z > 0) sees through the
// reference-plane point (x, y): ray-marched with masking by the height field.
MaterialHit TraceFromViewer(const Material& material, double x_m, double y_m, const Eigen::Vector3d& wo);

// True when the height field blocks direction `wi` (unit) from the surface point `point`.
bool SelfShadowed(const Material& material, const Eigen::Vector3d& point, const Eigen::Vector3d& wi);

// BRDF times cosine, f(wi, wo) * max(0, n.wi): the radiance leaving `hit` toward `wo` per unit
// irradiance measured perpendicular to `wi`. Lambertian albedo/pi plus a GGX lobe (Smith G,
// Schlick F). Shadowing is the caller's business.
Eigen::Vector3f ReflectedRadiance(const Material& material, const MaterialHit& hit,
                                  const Eigen::Vector3d& wi, const Eigen::Vector3d& wo);

struct TrueBtfRequest {
  double theta_i_deg = 0, phi_i_deg = 0, theta_o_deg = 0, phi_o_deg = 0;
  int size = 512;               // texels per side
  double patch_m = 0.064;       // physical side of the square patch (the rig's boards)
  Eigen::Vector2d offset_m{0, 0};  // where the patch centre sits in the material
  // Stratified samples per texel axis: 1 point-samples the texel centre; more average the
  // texel's footprint as a camera pixel does (no aliasing of fine mesostructure).
  int samples_per_axis = 1;
  // The material turned counter-clockwise (patch frame, about the patch centre) by this angle:
  // the truth of a synthesized patch pasted with that rotation.
  double material_rotation_deg = 0;
};

// A request for the pair of unit directions (patch frame) `light`, `view`.
TrueBtfRequest TrueBtfRequestFor(const Eigen::Vector3d& light, const Eigen::Vector3d& view, int size,
                                 int samples_per_axis = 1);

// One true BTF slice: orthographic view from (theta_o, phi_o), directional light from
// (theta_i, phi_i) with unit perpendicular irradiance, linear RGB radiance on the texel grid
// of a resampled slice (docs/formats.md: texel (i, j) centre at x = -P/2 + (i+0.5)P/N,
// y = P/2 - (j+0.5)P/N, so rows run from +y down to -y). With samples_per_axis > 1 each texel is
// the mean over a regular grid of points inside its square.
Image RenderTrueBtfSlice(const Material& material, const TrueBtfRequest& request, int num_threads = -1);

// A request's directions and turn in the material's frame.
struct TrueBtfFrame {
  explicit TrueBtfFrame(const TrueBtfRequest& r);
  Eigen::Vector3d wi, wo;  // unit, material frame
  Eigen::Matrix2d turn;    // patch frame -> material frame
};

// The reference-plane point (material frame, metres) that sample (sx, sy) of texel (i, j) looks
// through; the view ray from there does not depend on the light.
Eigen::Vector2d TexelSamplePoint(const TrueBtfRequest& r, const TrueBtfFrame& frame, int i, int j, int sx, int sy);

// The radiance a hit sends toward `wo` under `wi`: black when the height field shadows it.
Eigen::Vector3f LitRadiance(const Material& m, const MaterialHit& hit, const Eigen::Vector3d& wi, const Eigen::Vector3d& wo);

// Patch-frame coordinate of a texel centre (see RenderTrueBtfSlice).
inline Eigen::Vector2d TexelCentre(int i, int j, int size, double patch_m) {
  return {-patch_m / 2 + (i + 0.5) * patch_m / size, patch_m / 2 - (j + 0.5) * patch_m / size};
}

}  // namespace mesocap

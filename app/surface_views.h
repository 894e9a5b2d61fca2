// What decorate's previews and render share: lights placed from the camera, and one light's
// render of a dressed mesh written as a PNG.
#pragma once

#include <filesystem>
#include <vector>

#include "core/status.h"
#include "mesh/surface_map_file.h"
#include "mesh/surface_render.h"
#include "mesh/surface_shading.h"

namespace mesocap::app {

// Three lights for previews, in the camera's frame turned into the mesh's: from the upper left,
// from the camera, and grazing from the right.
std::vector<RenderLight> PreviewLights(const RenderCamera& camera);

// A light circling the view axis at 45 deg elevation: frame k of n.
RenderLight SweepLight(const RenderCamera& camera, int k, int n);

// Shades (per vertex, or per pixel through a quilt's atlas map), renders and writes an 8-bit sRGB PNG; `lit_share` (optional) the share of the mesh's
// pixels the light reaches.
Status RenderDressedToPng(const SurfaceScene& scene, const SurfaceAppearance& appearance, const DressedMesh& dressed,
                          const RenderCamera& camera, const RenderLight& light, double exposure,
                          const std::filesystem::path& path, int num_threads, double* lit_share = nullptr);

}  // namespace mesocap::app

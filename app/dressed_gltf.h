// A dressed mesh as a glTF 2.0 asset any viewer opens: the mesh with an atlas (mesh/atlas.h), its
// surface map baked texel by texel into the atlas (mesh/atlas_bake.h), and the exemplar's material
// maps (app/material_maps.h) carried through it: base colour, metallic-roughness and normal
// textures. Tangents are the surface map's frames (s, with n x s the bitangent), so a normal
// texel holds the sample's normal in its own frame.
#pragma once

#include "core/session_layout.h"
#include "core/status.h"
#include "export/ggx_fit.h"
#include "mesh/atlas.h"
#include "mesh/surface_map_file.h"
#include "synth/synth_map.h"

namespace mesocap::app {

struct DressedGltfFigures {
  int atlas_size = 0, charts = 0, vertices = 0;
  double fill = 0;
  bool wide_indices = false;
};

// Writes into `folder` (existing): the asset, its buffer and the three textures.
StatusOr<DressedGltfFigures> WriteDressedGltf(const GltfFolder& folder, const DressedMesh& dressed, const Atlas& atlas,
                                              const SynthMap& atlas_map, const GgxMaterialMaps& sample_maps);

}  // namespace mesocap::app

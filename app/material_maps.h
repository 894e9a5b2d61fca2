// A material's glTF maps (base colour, roughness, metallic, normal: export/ggx_fit.h) per sample
// texel, and carried through a texture-coordinate map: what the session export's gltf_synth/ and
// decorate's gltf/ write.
#pragma once

#include "core/progress.h"
#include "core/status.h"
#include "export/ggx_fit.h"
#include "synth/exemplar.h"
#include "synth/synth_map.h"

namespace mesocap::app {

// The fitted material enlarged by a synthesis map: each output texel takes its source texel's
// parameters, the normal turned with the patch (the map's rotation, counter-clockwise in the
// patch frame).
GgxMaterialMaps ApplyMapToMaterial(const SynthMap& map, const GgxMaterialMaps& maps);

// An exemplar's maps: a BTF's GGX fit (its index, `board` for a session's slices); a PTM's albedo
// and normals (roughness 1, not metallic); an image as the base colour (flat, rough, not metallic).
StatusOr<GgxMaterialMaps> ExemplarMaterialMaps(const Exemplar& exemplar, int board, int num_threads,
                                               const ProgressFn& progress = nullptr);

}  // namespace mesocap::app

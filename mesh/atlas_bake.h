// A per-vertex surface map carried onto an atlas texel by texel, so a glTF asset can hold it in
// ordinary textures: each atlas texel inside a triangle finds its surface point, the triangle's
// vertex nearest to it, and continues that vertex's sample coordinate by the point's offset in the
// vertex's frame (sample x along s, rows against t, one texel per texel size): the texture between
// vertices is the sample's own detail (Tong §6 blends vertex colours instead). Texels outside every
// chart take the coordinate of a chart texel within the gutter, so filtering never reads black.
#pragma once

#include "core/status.h"
#include "mesh/atlas.h"
#include "mesh/atlas_texels.h"
#include "mesh/surface_textons.h"
#include "mesh/tangent_frames.h"
#include "synth/synth_map.h"

namespace mesocap {

// The sample coordinate the map gives surface point `p` of face f: its nearest corner's coordinate
// continued by the offset (clamped into the sample).
Eigen::Vector2f ContinuedCoordinate(const TriangleMesh& mesh, const TangentFrames& frames, const SurfaceMap& map, int f,
                                    const Eigen::Vector3d& p);

// A map of atlas.size x atlas.size texels into the sample (patch ids: chart ids; texels beyond
// the gutter keep patch -1 and coordinate 0).
SynthMap BakeSurfaceMap(const TriangleMesh& mesh, const TangentFrames& frames, const SurfaceMap& map, const Atlas& atlas,
                        const AtlasTexels& texels, int gutter = 2);

// Each of `gutter` rounds, the empty texels beside filled ones copy one (left, right, up, down).
void FillAtlasGutter(SynthMap* map, int gutter);

}  // namespace mesocap

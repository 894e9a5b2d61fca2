// Surface texton maps (Tong et al. 2002 §5): per mesh vertex a sample texture coordinate and a
// texton label, synthesized vertex by vertex from the sample's 2D texton map, with every
// neighbourhood distance summed from the textons' dot-product matrix Gamma (no appearance
// vectors), and candidates from the k-coherence search.
//
// - Neighbourhoods: the triangles around a vertex are projected onto its (s, t) plane (the
//   tangent frame, mesh/tangent_frames.h) and the N x N template resampled in them, each slot a
//   surface texton w0 t_i0 + w1 t_i1 + w2 t_i2 (barycentric weights, Tong eq. 1); a slot no
//   projected front-facing triangle covers takes the default texton. Slot (dx, dy) lies at
//   (dx, -dy) x spacing in the (s, t) plane: sample rows run down, t runs up.
//   ||sum w_a t_a - t_j||^2 = sum_a w_a D(a, j) - 1/2 sum_ab w_a w_b D(a, b), D the squared
//   texton distances, so a slot costs three table lookups per candidate.
// - Candidates (Tong §5.2 on surfaces): every 1-ring neighbour u's coordinate, forward-shifted by
//   u's offset from the vertex in the vertex's plane, and that texel's k - 1 most similar texels
//   (the plane method's lists, synth/texton_sample.h); plus the vertex's own coordinate.
// - Multi-resolution: a mesh pyramid (mesh/mesh_pyramid.h, a quarter of the vertices per level)
//   matched to the texton analysis' Gaussian stack: at level l the template's spacing is 2^l
//   texels, 2^l x the texel size on the surface. The coarsest level starts from random texels;
//   each finer vertex continues its nearest coarser vertex's coordinate by its offset in that
//   vertex's frame, jittered (Lefebvre & Hoppe 2005's upsampling; Tong's first pass derives the
//   coordinate from the coarser level the same way).
// - Correction: `passes` passes per level; each pass in sub-passes over a colouring of the
//   vertex graph (no two neighbours share a colour), every vertex of a sub-pass corrected against
//   the state the sub-pass began with (so the result does not depend on the thread count), the
//   plane method's interleaved sub-passes carried onto meshes. As on the plane, a candidate that
//   is the source of a neighbour is never chosen (no stretched texels), and a candidate that
//   continues a neighbour is favoured by `coherence`.
// Changes from Tong, each measured with bench_surface_textons (a flat grid mesh, where the plane's
// measures apply; subband distance as a ratio to random tiling's, 96-texel crops, 256 x 256):
// - A slot takes the texton of the nearest vertex of its triangle, not the barycentric mix: on
//   the simplified coarse levels most slots fall inside triangles whose vertices differ, and the
//   mixes, nearer the mean texton, pulled the synthesis toward plain regions: sand 3.42x -> 2.37x,
//   stones 2.39x -> 1.90x, brick 1.57x -> 1.24x. (`slot_textons` keeps Tong's mix.)
// - As on the plane (texton_synthesis.h): his second pass matched two-level
//   neighbourhoods against a pyramid; the stack's blurred levels carry the coarse context instead.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/progress.h"
#include "core/status.h"
#include "mesh/tangent_frames.h"
#include "mesh/triangle_mesh.h"
#include "synth/texton_analysis.h"
#include "synth/texton_sample.h"

namespace mesocap {

// What a template slot holds: Tong's eq. 1, the barycentric mix of the three textons of the
// triangle containing it, or the texton of that triangle's nearest vertex (the default: measured
// better, see below).
enum class SlotTextons { kNearestVertex, kInterpolated };

struct SurfaceTextonOptions {
  int k = 11;              // k-coherence (Tong: 11; 1 for "natural" textures)
  int neighbourhood = 5;   // N x N template
  int levels = 0;          // pyramid levels (0: as many as the analysis and the mesh allow)
  int passes = 2;          // correction passes per level
  double jitter = 0.5;     // upsampled coordinates move by up to this x the level's spacing
  double coherence = 0.5;  // the plane method's bias toward continuing a neighbour
  double texel_size = 0;   // surface length of one sample texel (0: the mesh's mean edge length)
  SlotTextons slot_textons = SlotTextons::kNearestVertex;
  uint32_t seed = 1;
  int num_threads = -1;
  // The sample's levels and lists made once (MakeSampleLevels with this analysis, neighbourhood
  // and k) for several meshes; null: made here.
  const std::vector<SampleLevel>* sample_levels = nullptr;
  Status Check() const;
};

// Per vertex of a mesh: where in the sample it copies from (texel coordinates, centres at + 0.5,
// as SynthMap's), and for texton maps its finest-level texton label.
struct SurfaceMap {
  std::string method;
  int sample_width = 0, sample_height = 0;
  double texel_size = 0;                // surface length of one sample texel
  std::vector<float> source_x, source_y;
  std::vector<int32_t> label;           // -1 where the method has none
  int size() const { return int(source_x.size()); }
  Eigen::Vector2i SourceTexel(int v) const;  // the texel a vertex copies, clamped into the sample
};

struct SurfaceTextonLevelReport {
  int vertices = 0;
  double uncovered_slots = 0;  // share of template slots no triangle covered (default texton)
  double mean_candidates = 0;
};

struct SurfaceTextonReport {
  std::vector<SurfaceTextonLevelReport> levels;  // finest first
  double texel_size = 0;
  double seconds_pyramid = 0, seconds_lists = 0, seconds_templates = 0, seconds_synthesis = 0, seconds = 0;
};

// Synthesizes a map for `mesh` (its UVs, if any, are ignored) from `analysis` (of the sample the
// map will index). Frames are the finest level's; coarser levels take the frame of the nearest
// finest vertex.
StatusOr<SurfaceMap> SurfaceTextonSynthesis(const TriangleMesh& mesh, const TangentFrames& frames,
                                            const TextonAnalysis& analysis, const SurfaceTextonOptions& options,
                                            SurfaceTextonReport* report, const ProgressFn& progress = nullptr);

}  // namespace mesocap

namespace mesocap {

// How a per-vertex map uses the sample, over the mesh's edges: `repeats` the share whose two
// vertices copy the same texel (a stretched texel: a streak), `coherent` the share whose texels
// continue each other (the second vertex's texel within one texel of where the first's continues
// by the edge in the first's frame: inside a patch), `texels_used` the share of the sample's
// texels some vertex copies.
struct SurfaceMapUsage {
  double repeats = 0, coherent = 0, texels_used = 0;
};
SurfaceMapUsage MeasureSurfaceMap(const TriangleMesh& mesh, const TangentFrames& frames, const SurfaceMap& map);

}  // namespace mesocap

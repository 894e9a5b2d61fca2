// The sample's side of texton synthesis, shared by the plane (texton_synthesis.h) and mesh
// surfaces (mesh/surface_textons.h): per stack level, every texel's neighbourhood of labels and
// its list of most similar texels (the k-coherence lists, Tong 2002 §5.2), with the distance table
// every neighbourhood distance is summed from.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "core/status.h"
#include "synth/texton_analysis.h"

namespace mesocap {

inline constexpr float kTextonInfinity = std::numeric_limits<float>::infinity();

struct Offset {
  int dx = 0, dy = 0;
};

// The n x n template around a texel without the texel itself, nearest offsets first: a distance
// summed in this order passes a candidate's bound sooner (near texels differ most).
std::vector<Offset> Square(int n);

// One stack level of the sample with what the search needs: per texel the labels of its
// neighbourhood (spaced by the level's spacing; `outside` where a slot leaves the sample), and per
// texel the list of its most similar others. Every texel is a candidate.
struct SampleLevel {
  const TextonLevel* level = nullptr;
  int spacing = 1;
  // Per label, and for `outside`, a row of distances to every label, then to `outside`: a slot
  // beyond the sample costs half the typical distance between two of the sample's texels
  // (kOutsideCost), and nothing against another such slot.
  std::vector<float> distances;
  int stride = 0, outside = 0;
  std::vector<Offset> slots;     // the template
  std::vector<uint16_t> vectors;  // texels x slots
  int list_length = 0;
  std::vector<int32_t> nearest;  // texels x list_length: the texel itself, then similar others

  int width() const { return level->width; }
  int height() const { return level->height; }
  int texels() const { return level->width * level->height; }
  int slot_count() const { return int(slots.size()); }
  const uint16_t* vector(int t) const { return vectors.data() + size_t(t) * slots.size(); }
  const float* Row(int label) const { return distances.data() + size_t(label) * stride; }
  bool Inside(int x, int y) const { return x >= 0 && y >= 0 && x < width() && y < height(); }
};

// A slot beyond the sample costs this times the typical distance between two sample texels.
extern const double kOutsideCost;

SampleLevel MakeSampleLevel(const TextonLevel& level, int n);

// A neighbourhood to match: one distance-table row per slot.
struct Query {
  std::vector<const float*> rows;
  // Sum over slots; stops once it exceeds `bound` (a candidate that cannot win).
  float Distance(const uint16_t* candidate, float bound) const {
    float d = 0;
    const size_t n = rows.size();
    size_t i = 0;
    for (; i + 4 <= n; i += 4) {  // independent pairs: no chain of dependent adds
      d += (rows[i][candidate[i]] + rows[i + 1][candidate[i + 1]]) + (rows[i + 2][candidate[i + 2]] + rows[i + 3][candidate[i + 3]]);
      if (d > bound) return d;
    }
    for (; i < n; ++i) d += rows[i][candidate[i]];
    return d;
  }
};

Query SampleQuery(const SampleLevel& s, int t);

// The similar-texel list of every sample texel: the texel itself, then the k - 1 nearest others
// by the exact distance among kRerankFactor x as many nearest by summary, none within the level's
// spacing (at least 2) of the texel: on a blurred level those are near copies of it, and on the
// finest its direct neighbours, which would stretch it across the output.
// Returns false when cancelled (core/cancel.h: each block checks, so Ctrl-C stops it within a block).
bool BuildNearestLists(SampleLevel& s, int k, int num_threads);

// Levels 0..levels-1 of `analysis` over n x n templates, with their lists when k > 0. They depend
// on nothing else, so one set serves every synthesis from the analysis with the same n and k (a
// decorate stage's meshes: the lists are most of a small mesh's time). Status::Cancelled on Ctrl-C.
StatusOr<std::vector<SampleLevel>> MakeSampleLevels(const TextonAnalysis& analysis, int levels, int n, int k, int num_threads);

// Whether `samples` were made by MakeSampleLevels from `analysis` with n and k, for `levels` levels.
bool SampleLevelsFit(const std::vector<SampleLevel>& samples, const TextonAnalysis& analysis, int levels, int n, int k);

}  // namespace mesocap

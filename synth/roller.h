// The BTF roller (Haindl & Hatka): a double toroidal tile cut from the sample by optimal
// horizontal and vertical cuts through an overlap band, both closed on the torus through one
// optimal vertex, so the tile repeats seamlessly in both directions; optionally n tiles with
// identical borders and different interiors, chosen at random per cell of the output.
// The analysis runs once on the features (the error summed over every slice, through the SVD
// geometry maps) and serves every light and view: the slices are registered on one texel grid, so
// one tile set keeps the mesostructure identical under all of them.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/image.h"
#include "core/status.h"
#include "synth/synth_map.h"

namespace mesocap {

struct RollerOptions {
  int width = 512, height = 512;  // output texels
  int tiles = 1;                  // n: tiles with identical borders (Haindl §2.6)
  double alpha = 2.0;             // overlap h = N / (alpha f)  (Haindl eq. 3)
  double interior_alpha = 4.0;    // the same for the interior replacement (§2.6)
  // Used when the head-on slice has no dominant low frequency (its spectrum's strongest
  // non-zero frequency is not clearly above the others): the paper's worst case f = 2.
  double fallback_frequency = 2.0;
  uint32_t seed = 1;
  int num_threads = -1;
  Status Check() const;
};

struct RollerTiles {
  int tile_width = 0, tile_height = 0;
  // tiles[k][t * tile_width + u]: the sample texel tile k shows at (u, t).
  std::vector<std::vector<Eigen::Vector2i>> tiles;
};

struct RollerReport {
  double frequency_rows = 0, frequency_columns = 0;  // f_r1, f_r2: cycles over the sample's height, width
  bool frequency_fallback = false;
  std::string fallback_reason;
  int overlap_rows = 0, overlap_columns = 0;         // h, v
  int tile_width = 0, tile_height = 0;
  int rectangle_x = 0, rectangle_y = 0;              // where the tile's rectangle sits in the sample
  int vertex_row = 0, vertex_column = 0;             // r*, inside the corner overlap
  double mean_cut_error = 0;                         // mean psi along both cuts (feature units squared)
  std::vector<Eigen::Vector2i> interior_sources;     // sample position of each extra tile's interior
  int tiles_made = 0;  // may be fewer than asked: the sample had no room for another distinct interior
  double seconds_analysis = 0, seconds_synthesis = 0;
};

// Dominant low frequency per axis of a luminance plane (cycles across its height and width):
// the strongest non-zero frequency of each axis's amplitude spectrum. Returns false when neither
// stands out (peak below twice the median), with the reason in `why`.
bool DominantFrequencies(const Image& luminance, double* rows, double* columns, std::string* why);

// Analysis: the tiles from the sample's features and its head-on luminance.
StatusOr<RollerTiles> AnalyseRoller(const Image& features, const Image& head_on_luminance, const RollerOptions& options,
                                    RollerReport* report);

// Synthesis: repeat the tiles over the output, a uniformly random tile per cell.
SynthMap RollTiles(const RollerTiles& tiles, int sample_width, int sample_height, int width, int height, uint32_t seed);

// Both steps.
StatusOr<SynthMap> RollerSynthesis(const Image& features, const Image& head_on_luminance, const RollerOptions& options,
                                   RollerReport* report);

// The tile as an image of features (for the wrap-around seam check).
Image TileFeatures(const RollerTiles& tiles, int tile, const Image& features);

}  // namespace mesocap

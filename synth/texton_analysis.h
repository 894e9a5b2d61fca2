// Texton analysis (Tong et al. 2002 §4, after Leung & Malik's 3D textons): a BTF sample's slices
// are filtered with the 48 Gaussian-derivative filters; n_s representative slices are chosen by
// K-means over each slice's image appearance vector (its responses on a regular subsampling
// grid), the slice nearest each centre; the texels' concatenated responses over those slices are
// K-means clustered into n_t textons plus a default texton (their mean); each texel gets the label
// of its nearest texton (the 2D texton map t_in), and the textons' dot products form the matrix
// Gamma. The appearance vectors are then discarded: synthesis needs only the map and Gamma.
//
// One change from the paper, measured in the closing note of the texton issue: the concatenated
// responses (n_s x 48 values per texel) are projected onto their top principal directions
// (`dimensions`, by the streamed randomized SVD that makes a BTF exemplar's features) before the
// clustering, so memory stays bounded by the sample's size, not its slice count. The projection
// is exact when n_s x 48 <= dimensions, and distances and dot products are those of the
// projections.
//
// Multi-resolution synthesis needs a texton map and Gamma at every level. The levels form a
// Gaussian stack (Lefebvre & Hoppe 2005), not Tong's pyramid: level l keeps every texel of the
// sample, its texel vectors blurred as far as l pyramid reductions would, and synthesis reads its
// neighbourhoods with a spacing of 2^l texels. A pyramid's coarse levels offer only (side / 2^l)^2
// source positions, so a texel-by-texel synthesis on them snaps to a coarse grid; the stack offers
// every texel at every level. Level l has a quarter of the textons of the level above (Tong §5.1),
// at least 16.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "core/image.h"
#include "core/progress.h"
#include "core/status.h"

namespace mesocap {

inline constexpr int kMaxTextonLevels = 8;

struct TextonAnalysisOptions {
  int representative_slices = 400;  // n_s (Tong: 400); all slices when there are no more
  int textons = 400;                // n_t at the finest level (Tong: 400); a quarter per coarser level
  int levels = 0;                   // stack levels (Tong: three or four); 0: while side / 2^l >= 3
  int grid_points = 256;            // texels on a slice's subsampling grid (its appearance vector)
  int dimensions = 64;              // principal directions kept of the concatenated responses
  int kmeans_iterations = 30;
  // The slices' own values over each texel's 3 x 3 neighbourhood, times this, join the filter
  // responses (0: responses only, as Tong).
  double texel_value_weight = 1.0;
  uint32_t seed = 1;
  int num_threads = -1;
  Status Check() const;
};

// The analysis of one stack level: the sample's size, its neighbourhoods spaced `spacing` texels.
struct TextonLevel {
  int width = 0, height = 0;
  int spacing = 1;                // 2^l
  int textons = 0;                // labels 0..textons-1 are textons; label `textons` is the default one
  std::vector<int32_t> labels;    // the 2D texton map, row-major
  Eigen::MatrixXd gamma;          // (textons + 1)^2 dot products t_i . t_j, the default texton last
  double energy_kept = 1.0;       // share of the responses' energy the projections keep
  int label(int x, int y) const { return labels[size_t(y) * width + x]; }
  int default_texton() const { return textons; }
};

struct TextonAnalysis {
  int slice_count = 0;                     // slices of the sample
  std::vector<int> representative_slices;  // indices of the n_s slices clustered
  std::vector<TextonLevel> levels;         // finest first
  double seconds = 0;
};

// What the analysis discards, kept for tests: per level, the texel vectors clustered (width x
// height x dimensions) and the textons (rows, without the default one).
struct TextonVocabulary {
  Image texel_vectors;
  Eigen::MatrixXd textons;
};

// `read_luminance(k)` returns slice k's luminance (one channel, linear; every slice the same
// size). A sample with one slice (a plain image) works: its responses are its vectors.
StatusOr<TextonAnalysis> AnalyzeTextons(int slice_count, const std::function<StatusOr<Image>(int)>& read_luminance,
                                        const TextonAnalysisOptions& options, const ProgressFn& progress = nullptr,
                                        std::vector<TextonVocabulary>* vocabulary = nullptr);

// Squared distances ||t_i - t_j||^2 = gamma_ii + gamma_jj - 2 gamma_ij, as floats (clamped at 0):
// the table every neighbourhood distance of texton synthesis is summed from.
std::vector<float> TextonDistances(const TextonLevel& level);

// How many of the analysis' levels, finest first, leave the sample's shorter side at least
// `min_steps` steps of their spacing.
int LevelsSpanning(const TextonAnalysis& analysis, int min_steps);

// A multi-part float OpenEXR (docs/formats.md): per level a part "labels<l>" (channel "texton")
// and a part "gamma<l>" (channel "gamma"), with the analysis' parameters as attributes. Reading
// checks every label and the matrix (square, symmetric, finite) and names the file on error.
Status WriteTextonAnalysis(const std::filesystem::path& path, const TextonAnalysis& analysis);
StatusOr<TextonAnalysis> ReadTextonAnalysis(const std::filesystem::path& path);

}  // namespace mesocap

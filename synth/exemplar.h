// What a user hands to synthesis: a plain colour image (a BTF with one slice), a BTF folder
// (`mesocap reconstruct` output, or a session's measured slices of one board), or a .ptm.
// Matching never touches all slices: it uses `features`, one vector per texel: the image's
// linear colours, the BTF's geometry maps from a streamed SVD of its slices (Zhou 2005 §III-A,
// n = 40), or the PTM's per-colour polynomials in the orthonormal Legendre basis
// (reconstruct/ptm_legendre.h).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/image.h"
#include "core/progress.h"
#include "core/status.h"
#include "reconstruct/ptm.h"

namespace mesocap {

enum class ExemplarKind { kImage, kBtf, kPtm };
std::string ExemplarKindToString(ExemplarKind kind);

// One slice of a BTF exemplar on disk; directions are unit vectors in the patch frame.
struct ExemplarSlice {
  std::filesystem::path file;
  Eigen::Vector3d light = Eigen::Vector3d::UnitZ(), view = Eigen::Vector3d::UnitZ();
  double theta_i_deg = 0, phi_i_deg = 0, theta_o_deg = 0, phi_o_deg = 0;
};

struct ExemplarOptions {
  int svd_components = 40;  // n of Zhou §III-A: geometry maps kept from the SVD of the slices
  int svd_power_iterations = 1;  // randomized SVD (Halko et al.): passes that sharpen the basis
  // Divide each slice by its RMS value before the SVD, so every light and view weighs the same in
  // matching and cutting (false: the plain sum of squared errors over slices).
  bool normalize_slices = true;
  int board = -1;           // session slices: which board (-1: the most head-on one)
  // A BTF's geometry maps (the SVD over every slice); false: the slices and preview alone, all
  // that applying a map needs.
  bool features = true;
  int num_threads = -1;
  bool Check() const { return svd_components >= 1 && svd_power_iterations >= 0; }
};

struct Exemplar {
  ExemplarKind kind = ExemplarKind::kImage;
  std::filesystem::path path;
  int width = 0, height = 0;
  Image image;                        // kImage: linear colours
  std::vector<ExemplarSlice> slices;  // kBtf
  Ptm ptm;                            // kPtm
  Image features;                     // per texel matching vector (width x height x F)
  Image preview;                      // linear RGB, head-on lit: spectra and pictures
  double svd_energy_kept = 1.0;       // kBtf: share of the slices' energy the features keep

  // kBtf: slice k read from disk (linear RGB); error names the file.
  StatusOr<Image> ReadSlice(int k) const;
};

// Loads any exemplar; the error names the file and what is wrong with it. BTF folders: a
// folder or index.json of format "mesocap-btf" (reconstruct) or "mesocap-slices" (a session's
// slices/, or the session folder itself).
StatusOr<Exemplar> LoadExemplar(const std::filesystem::path& path, const ExemplarOptions& options = {},
                                const ProgressFn& progress = nullptr);

// An in-memory exemplar from one image (tests, and images already loaded).
Exemplar ImageExemplar(Image image);
// An in-memory BTF exemplar from slices already on disk (features computed as LoadExemplar does).
StatusOr<Exemplar> BtfExemplar(std::vector<ExemplarSlice> slices, const ExemplarOptions& options = {},
                               const ProgressFn& progress = nullptr);

// The exemplar's appearance as luminance images, for texton analysis: a BTF's slices, the image,
// or a PTM relit under 17 lights (head-on, 8 at 30 deg and 8 at 60 deg from the normal).
int AppearanceImageCount(const Exemplar& exemplar);
StatusOr<Image> AppearanceLuminance(const Exemplar& exemplar, int k);

// An image as a texels x channels matrix (row-major, sharing the image's memory).
using TexelMatrixMap = Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;
TexelMatrixMap TexelMatrix(const Image& image);

// The image divided by the RMS of its values (unchanged if all are zero): a slice so normalised
// weighs the same in a distance whatever its exposure.
Image DividedByRms(Image image);

// Geometry maps of a set of same-size slices read one at a time (never all in memory): the
// top `components` left singular vectors of the texel x (slice, channel) matrix scaled by their
// singular values, so distances between texels' feature vectors approximate their distances over
// all slices. Randomized range finder with `power_iterations` passes; deterministic.
struct SliceFeatures {
  Image features;
  double energy_kept = 1.0;  // sum of kept squared singular values / Frobenius norm squared
};
StatusOr<SliceFeatures> GeometryMapsOfSlices(int count, const std::function<StatusOr<Image>(int)>& read_slice,
                                             int components, int power_iterations, bool normalize = true,
                                             int num_threads = -1,
                                             const ProgressFn& progress = nullptr);

}  // namespace mesocap

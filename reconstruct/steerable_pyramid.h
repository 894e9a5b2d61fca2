// Steerable pyramid in the frequency domain (Simoncelli & Freeman; the Portilla-Simoncelli
// construction): a high-pass residual, `levels` scales of `orientations` oriented band-pass
// subbands, each scale half the size of the previous, and a low-pass residual. The filters form
// a tight frame, so collapsing the bands gives the input back (to float round-off) and the
// energy of the input equals the energy of the bands. Ngan & Durand use 4 orientations and all
// scales; the statistical BTF matches the histogram of every band.
#pragma once

#include <vector>

namespace mesocap {

// One subband: a single-channel float plane, row-major.
struct PyramidBand {
  int width = 0, height = 0;
  std::vector<float> values;
};

struct SteerablePyramid {
  int width = 0, height = 0;  // of the input plane
  int levels = 0;
  int orientations = 0;
  // bands[0] high-pass residual (full size); then for level l = 0..levels-1 and orientation
  // o = 0..orientations-1, bands[1 + l*orientations + o] (size width>>l x height>>l);
  // bands.back() the low-pass residual (width>>levels x height>>levels).
  std::vector<PyramidBand> bands;

  int band_count() const { return static_cast<int>(bands.size()); }
};

struct SteerablePyramidOptions {
  int orientations = 4;
  // Number of band-pass scales; -1 means all: as many as keep the low-pass residual at least
  // 8 texels on its shorter side (the 1e-4 round trip holds for any value up to that).
  int levels = -1;
  bool Check() const;
};

// Largest number of scales for a plane of this size (see SteerablePyramidOptions::levels).
int MaxPyramidLevels(int width, int height);

// Decomposes a single-channel plane. Width and height must be divisible by 2^levels (the
// resampled slices are 2^k on a side); throws std::invalid_argument otherwise.
// Thread-safe: may be called from several threads at once.
SteerablePyramid BuildSteerablePyramid(const float* plane, int width, int height,
                                       const SteerablePyramidOptions& options = {});

// The inverse: the plane the bands describe (width*height values, row-major).
std::vector<float> CollapseSteerablePyramid(const SteerablePyramid& pyramid);

}  // namespace mesocap

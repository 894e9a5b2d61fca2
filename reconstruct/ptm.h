// Polynomial texture maps (Malzbender, Gelb & Wolters 2001): per pixel, a biquadratic in the
// projected light direction (lu, lv),
//   L(lu, lv) = a0 lu^2 + a1 lv^2 + a2 lu lv + a3 lu + a4 lv + a5,
// fitted by least squares to photographs taken under known light directions.
//
// Two models, named as in HP's .ptm format:
//   LRGB  one luminance polynomial per pixel times a per-pixel colour: c(l) = L(l) * rgb.
//         L is normalised per pixel (L is about 1 at the brightest measured light), so the
//         colour carries the magnitude and the polynomial the shape of the variation.
//   RGB   one polynomial per colour channel: c_k(l) = L_k(l).
//
// Light directions are in the surface frame with z the normal, x toward the image's right and y
// toward its top (the RTI and .lp convention, with (lu, lv) = (x, y) of the unit direction). A
// frame with y down the image (OpenCV camera axes) must have y negated, or viewers such as
// RTIViewer show the light mirrored top to bottom.
//
// Values are in the units of the input images (whatever encoding the caller read them in; RTI
// viewers expect display-encoded values, i.e. images read without linearisation).
#pragma once

#include <chrono>
#include <cstdint>

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/image_u8_io.h"
#include "core/status.h"

namespace mesocap {

enum class PtmFormat { kLrgb, kRgb };
std::string PtmFormatToString(PtmFormat format);  // "lrgb", "rgb"
bool StringToPtmFormat(const std::string& name, PtmFormat* format);

inline constexpr int kPtmCoefficients = 6;

// Luminance weights used by the LRGB model and by normals of the RGB model (ITU-R BT.601 luma,
// the Y of the YCbCr colour space JPEG files are stored in).
inline constexpr float kPtmLumaWeights[3] = {0.299f, 0.587f, 0.114f};

struct Ptm {
  PtmFormat format = PtmFormat::kLrgb;
  // LRGB: 6 channels, a0..a5 of the dimensionless luminance polynomial.
  // RGB: 18 channels, a0..a5 of the red polynomial, then green, then blue.
  Image coefficients;
  // LRGB only: 3 channels, the colour the luminance multiplies. Empty for RGB.
  Image rgb;

  int width() const { return coefficients.width(); }
  int height() const { return coefficients.height(); }
  // Number of polynomials per pixel: 1 (LRGB) or 3 (RGB).
  int polynomials() const { return format == PtmFormat::kLrgb ? 1 : 3; }
  // True when the image sizes and channel counts agree with `format`.
  bool IsConsistent() const;
};

struct PtmFitOptions {
  PtmFormat format = PtmFormat::kLrgb;
  // Lights closer than this (angle between directions) are reported as near-duplicates, in a
  // warning only: a repeated shot weighs its direction twice, which least squares takes in its
  // stride. Only an ill-conditioned light set is refused.
  double near_duplicate_light_deg = 0.5;
  // Condition number (sigma_max / sigma_min) of the light matrix, one row [lu^2, lv^2, lu lv,
  // lu, lv, 1] per light with each column scaled to unit length. Least squares amplifies photo
  // noise into the coefficients by up to this factor. Well-spread sets measure 3-10 (a dome,
  // random directions), sparse or one-sided ones up to 70 (lights in one azimuth quadrant); one
  // ring at a single elevation is singular. At 1000, 8-bit quantisation noise (1/(255 sqrt 12)
  // of full scale) grows to full scale along the weakest direction: the fit is then noise there
  // and the quantised .ptm relights its own photos wrongly, so the set is refused.
  double max_condition = 1000;
  double warn_condition = 100;  // above this, a warning names the missing directions
  // Below this, a pixel counts as black in the LRGB model (its polynomial and colour are zero).
  float black_level = 1e-6f;
  // Evaluate the fit at every light to report the RMS residual; costs about as much as the
  // fit itself, so a caller that only wants the coefficients fast may turn it off.
  bool compute_residual = true;
  int num_threads = -1;  // -1: all cores

  bool Check() const;
};

struct PtmFitReport {
  int num_lights = 0;
  int width = 0, height = 0;
  double light_matrix_condition = 0;  // of the column-normalised light matrix (PtmFitOptions)
  std::vector<std::string> warnings;  // near-duplicate lights, a poorly spread set
  double rms_residual =
      -1;  // over all pixels, channels and lights, in input units; -1: not computed
  double fit_seconds = 0;

  std::string Brief() const;
};

// The 6 basis values [lu^2, lv^2, lu lv, lu, lv, 1] for a light direction (any length > 0;
// (lu, lv) are the x and y of the normalised direction).
Eigen::Matrix<double, 1, 6> PtmBasis(const Eigen::Vector3d& light_dir);

struct PtmLightCheck {
  double condition = 0;               // of the column-normalised light matrix
  std::vector<std::string> warnings;  // near-duplicate lights, a poorly spread set
};

// Checks a light set can be fitted: at least 6 lights, all finite and non-zero, not collinear in
// (lu, lv), and a light matrix conditioned within options.max_condition (e.g. not all at one
// elevation, where lu^2 + lv^2 is constant). A refusal says which directions are missing. On
// success *check (if given) receives the condition number and the warnings.
Status ValidatePtmLights(const std::vector<Eigen::Vector3d>& light_dirs,
                         const PtmFitOptions& options, PtmLightCheck* check = nullptr);

// Fits a PTM to `images[i]` photographed under `light_dirs[i]` (surface frame, z = normal),
// one shared least-squares solve for all pixels: coefficients = pinv(A) * observations with A
// the n x 6 light matrix, applied block by block over the rows on all cores. Images must all have the same size and channel
// count; 1 channel (grey, replicated to RGB), 3, or 4 (alpha ignored).
StatusOr<Ptm> FitPtm(const std::vector<Image>& images,
                     const std::vector<Eigen::Vector3d>& light_dirs,
                     const PtmFitOptions& options = {}, PtmFitReport* report = nullptr);

// The same fit on 8-bit images as stored (core/image_u8_io.h): a value v counts as
// v * kU8ToUnit, as ReadImage(path, {.linearize = false}) reads it, so the result agrees with the
// float overload on ImageU8ToFloat(images) to float round-off (same kernel). The inputs stay
// 8-bit: the fit streams over row blocks, converting only the block in hand to float, so memory
// is the inputs (n x pixels x channels bytes) plus the output.
StatusOr<Ptm> FitPtm(const std::vector<ImageU8>& images,
                     const std::vector<Eigen::Vector3d>& light_dirs,
                     const PtmFitOptions& options = {}, PtmFitReport* report = nullptr);

// The same fit row by row, for callers that stream their photos (fit-ptm decodes bands of rows
// and never holds a photo or the result whole). Rows may come in any order and grouping: each
// row's result, the residual included, is the same as FitPtm's, bit for bit.
class PtmRowFitter {
 public:
  // Checks the lights (ValidatePtmLights) and the shape.
  static StatusOr<PtmRowFitter> Create(const std::vector<Eigen::Vector3d>& light_dirs, int width, int height,
                                       int channels, const PtmFitOptions& options = {});
  // A Ptm of `rows` rows (not initialised) in this fit's format and width: the whole result, or
  // a band of it.
  Ptm NewRows(int rows) const;
  // Fits rows [y0, y1) into rows [0, y1 - y0) of *into (from NewRows) on options.num_threads
  // threads: row(i, y) is row y of image i (width x channels values; 8-bit values count as
  // v * kU8ToUnit), called from those threads. `fitted(y)`, if given, runs on the same thread
  // right after row y is fitted (while it is in cache).
  void FitRows(int y0, int y1, const std::function<const float*(int image, int y)>& row, Ptm* into,
               const std::function<void(int y)>& fitted = {});
  void FitRows(int y0, int y1, const std::function<const uint8_t*(int image, int y)>& row, Ptm* into,
               const std::function<void(int y)>& fitted = {});
  // Fits row y alone, on the calling thread, into row y - y0 of *into: for callers that schedule
  // rows among other work (fit-ptm fits one band of rows while it decodes the next).
  void FitRow(int y, int y0, const std::function<const uint8_t*(int image, int y)>& row, Ptm* into);
  // Once every row is fitted: the light-set figures, the residual over all rows and the time
  // since Create.
  void Report(PtmFitReport* report) const;

 private:
  PtmRowFitter() = default;
  template <typename T>
  void FitRowsOf(int y0, int y1, const std::function<const T*(int, int)>& row, float scale, Ptm* into,
                 const std::function<void(int)>& fitted);
  template <typename T>
  void FitRowOf(int y, int y0, const std::function<const T*(int, int)>& row, float scale, Ptm* into);
  template <typename T>
  void FitRow(int y, const T* const* rows, float scale, float* coef_row, float* rgb_row);

  PtmFitOptions options_;
  PtmLightCheck light_check_;
  int n_ = 0, width_ = 0, height_ = 0, channels_ = 0;
  std::vector<float> p_, a_f_;  // pinv(A) row-major 6 x n; A row-major n x 6
  std::vector<double> row_sse_;
  std::chrono::steady_clock::time_point start_;
};

// Where a point light close to the sample makes the light direction differ from pixel to pixel
// (a flash 0.5 m from a 64 mm patch: up to ~7 deg): light i's unit direction at pixel (x, y),
// surface frame.
using PixelLightFn = std::function<Eigen::Vector3d(int light, int x, int y)>;

// The same least-squares fit with a light matrix per pixel (normal equations, 6 x 6 per pixel,
// in double). Slower than the shared solve; RGB and LRGB as above. A pixel whose directions are
// degenerate (fewer than 6 lights or a singular matrix) gets zero coefficients and is counted in
// `degenerate_pixels`. `residual_map`, when given, receives each pixel's RMS residual over its
// lights and channels (zero where degenerate).
StatusOr<Ptm> FitPtmPerPixelLights(const std::vector<Image>& images, const PixelLightFn& light_dir,
                                   const PtmFitOptions& options = {}, PtmFitReport* report = nullptr,
                                   int* degenerate_pixels = nullptr, Image* residual_map = nullptr);

// Directions from point lights at `lights_m` (patch frame, metres) to the texel centres of a
// size x size slice of side patch_m (texel (x, y) centre at (-P/2 + (x+0.5)P/N, P/2 - (y+0.5)P/N)).
PixelLightFn PointLightDirections(std::vector<Eigen::Vector3d> lights_m, int size, double patch_m);

// Evaluates the PTM for one light direction: a 3-channel image, clamped to [0, 1] as the RTI
// viewers do (set clamp = false to get the raw polynomial values).
Image RelightPtm(const Ptm& ptm, const Eigen::Vector3d& light_dir, bool clamp = true,
                 int num_threads = -1);

struct PtmNormalsAlbedo {
  Image normals;  // 3 channels, unit vectors in the surface frame (z = up)
  Image albedo;   // 3 channels: the colour at the light direction of the luminance maximum
};

// Surface normals from the maximum of the luminance polynomial over the unit disk of (lu, lv)
// (Malzbender 2001, eq. 16 where the maximum is interior), and an albedo estimate: the colour
// the PTM predicts when lit along that normal (for a Lambertian surface, rho * (n . n) = rho).
PtmNormalsAlbedo PtmNormalsAndAlbedo(const Ptm& ptm, int num_threads = -1);

// Light direction (unit, z >= 0) at which the polynomial a0..a5 peaks over the unit disk.
Eigen::Vector3d PtmMaximumDirection(const double a[6]);

}  // namespace mesocap

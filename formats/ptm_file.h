// HP's polynomial texture map file (.ptm, version 1.2), the two uncompressed formats RTIViewer
// and HP's PTMviewer read: PTM_FORMAT_LRGB and PTM_FORMAT_RGB.
//
// Layout: ASCII lines "PTM_1.2", the format name, width, height (each on its own line), a line
// of six float scales, a line of six integer biases, then binary coefficient bytes decoded as
//   a_k = (byte - bias_k) * scale_k        (k = 0..5 for lu^2, lv^2, lu lv, lu, lv, 1)
// in units where 255 is full intensity. Rows run bottom to top, pixels left to right.
//   LRGB: W*H*6 coefficient bytes interleaved per pixel, then W*H*3 RGB bytes; a pixel relights
//         as rgb_byte * L(lu, lv) / 255.
//   RGB:  three blocks of W*H*6 coefficient bytes (red, green, blue), one scale/bias per
//         coefficient index shared by the three channels.
//
// A mesocap Ptm (reconstruct/ptm.h) holds values in [0, 1] units: file coefficient =
// 255 * Ptm coefficient, rgb byte = round(255 * Ptm rgb).
#pragma once

#include <array>
#include <filesystem>
#include <functional>
#include <vector>

#include "core/status.h"
#include "formats/ptm_quantize.h"
#include "reconstruct/ptm.h"

namespace mesocap {

// Per-coefficient quantisation, in file units.
struct PtmQuantization {
  std::array<float, 6> scale{1, 1, 1, 1, 1, 1};
  std::array<int, 6> bias{0, 0, 0, 0, 0, 0};
};

struct PtmWriteOptions {
  // Whole-number scales, so every decoded coefficient is an integer. RTIViewer (and viewers
  // derived from it) truncate decoded coefficients to int; with integer scales they decode
  // exactly what ReadPtmFile does. The step is then at least 1/255 of full intensity, which keeps
  // relighting within about 0.5/255 RMS of the float fit. false: the finest step the range
  // allows (float scales), for readers that keep coefficients as floats.
  bool integer_scales = true;
};

// The scale and bias per coefficient index that cover the full range of that coefficient over the
// whole image (all channels for RGB) with the finest step allowed: no coefficient is clipped, and
// each is decoded within scale/2 of its value. The bias may be any integer in [0, 255].
PtmQuantization ChoosePtmQuantization(const Ptm& ptm, bool integer_scales = true);

// Writes `ptm` atomically (temp file, fsync, rename). Errors name the file. `quantization`, if
// given, receives the scales and biases written.
Status WritePtmFile(const std::filesystem::path& path, const Ptm& ptm,
                    const PtmWriteOptions& options = {}, PtmQuantization* quantization = nullptr);

// A PTM that is not held whole, as the writer reads it (fit-ptm parks its fit in a scratch file):
// its shape, the range of all its coefficients (which fixes the quantisation before any row is
// written), and its rows. Row y's coefficients (width x 6 floats per polynomial, as in
// Ptm::coefficients) and, LRGB only, colours (width x 3): called from several threads at once,
// each passing its own buffer for a row that must be read from somewhere.
struct PtmRowSource {
  PtmFormat format = PtmFormat::kLrgb;
  int width = 0, height = 0;
  CoefficientRange range = CoefficientRange::Empty();
  std::function<StatusOr<const float*>(int y, std::vector<float>* buffer)> coefficients, rgb;
};

// The same file from such rows: byte for byte what WritePtmFile writes for the Ptm they come from.
// A non-finite range is refused.
Status WritePtmFile(const std::filesystem::path& path, const PtmRowSource& rows,
                    const PtmWriteOptions& options = {}, PtmQuantization* quantization = nullptr);

// Reads a PTM_1.2 file in the LRGB or RGB format. A truncated or malformed file gives an error
// naming the file and what was wrong.
StatusOr<Ptm> ReadPtmFile(const std::filesystem::path& path,
                          PtmQuantization* quantization = nullptr);

}  // namespace mesocap

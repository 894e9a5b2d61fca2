#include "core/chroma_detail.h"

#include <algorithm>
#include <vector>

#include "core/image_io.h"
#include "core/parallel.h"

namespace mesocap {
namespace {

constexpr int kWindowRadius = 2;  // 5x5: 3 and 7 did no better on the virtual materials
constexpr float kEps = 1e-4f;     // on values in [0, 1]; 1e-3 restores less of weave's detail
// Rows (and columns) beyond a band its output depends on: the pair average and the triangle
// filter reach 3, the window 2 more. Even, so the band's first row starts a chroma pair as the
// image's does (its first column is rounded down to even for the same reason).
constexpr int kHalo = 8;
// The window means the slopes need: of the low-passed luma, its square, the chroma, and their
// products.
enum Mean { kLow, kLow2, kCb, kLowCb, kCr, kLowCr, kMeans };

// One band's planes, kept per thread from band to band: fresh memory costs page faults.
struct Workspace {
  int width = 0, rows = 0;
  // JFIF's full-range Y'CbCr of the band's rows (values in [0, 1], chroma centred on 0) and the
  // luma as the chroma was sampled.
  std::vector<float> y, cb, cr, low, scratch;
  std::vector<float> across[kMeans], means[kMeans];
  float* Row(std::vector<float>& plane, int r) { return plane.data() + size_t(r) * width; }
  void Resize(int w, int r) {
    width = w, rows = r;
    for (std::vector<float>* plane : {&y, &cb, &cr, &low, &scratch}) plane->resize(size_t(w) * r);
    for (int m = 0; m < kMeans; ++m) across[m].resize(size_t(w) * r), means[m].resize(size_t(w) * r);
  }
};

void ToYCbCr(const ImageU8& srgb, int first_row, int first_column, Workspace& ws) {
  for (int r = 0; r < ws.rows; ++r) {
    const uint8_t* src = srgb.row(first_row + r) + 3 * size_t(first_column);
    float *y = ws.Row(ws.y, r), *cb = ws.Row(ws.cb, r), *cr = ws.Row(ws.cr, r);
    for (int x = 0; x < ws.width; ++x) {
      const float red = src[3 * x] * (1 / 255.0f), green = src[3 * x + 1] * (1 / 255.0f), blue = src[3 * x + 2] * (1 / 255.0f);
      const float luma = 0.299f * red + 0.587f * green + 0.114f * blue;
      y[x] = luma, cb[x] = (blue - luma) * (1 / 1.772f), cr[x] = (red - luma) * (1 / 1.402f);
    }
  }
}

// The two-tap upsampling of libjpeg's "fancy" filter: each output sample is 3/4 of its own
// low-resolution sample and 1/4 of the next one on its side (the edge one repeated).
inline float Triangle(float own, float side) { return 0.75f * own + 0.25f * side; }

// Along a row: the mean of each aligned pair of samples (the last one alone when the width is
// odd), upsampled back to the width. `low`: room for (width + 1) / 2 samples.
void LowpassAcross(const float* in, int width, float* out, float* low) {
  const int pairs = (width + 1) / 2;
  for (int k = 0; k < pairs; ++k) low[k] = 0.5f * (in[2 * k] + in[std::min(2 * k + 1, width - 1)]);
  for (int k = 0; k < pairs; ++k) {
    out[2 * k] = Triangle(low[k], low[std::max(k - 1, 0)]);
    if (2 * k + 1 < width) out[2 * k + 1] = Triangle(low[k], low[std::min(k + 1, pairs - 1)]);
  }
}

// The same down the band's rows (pairs start at its first row), from ws.low into ws.low.
void LowpassDown(Workspace& ws) {
  const int w = ws.width, rows = ws.rows, pairs = (rows + 1) / 2;
  for (int k = 0; k < pairs; ++k) {
    const float *a = ws.Row(ws.low, 2 * k), *b = ws.Row(ws.low, std::min(2 * k + 1, rows - 1));
    float* pair = ws.Row(ws.scratch, k);
    for (int x = 0; x < w; ++x) pair[x] = 0.5f * (a[x] + b[x]);
  }
  for (int k = 0; k < pairs; ++k) {
    const float* own = ws.Row(ws.scratch, k);
    const float *above = ws.Row(ws.scratch, std::max(k - 1, 0)), *below = ws.Row(ws.scratch, std::min(k + 1, pairs - 1));
    float* even = ws.Row(ws.low, 2 * k);
    for (int x = 0; x < w; ++x) even[x] = Triangle(own[x], above[x]);
    if (2 * k + 1 >= rows) continue;
    float* odd = ws.Row(ws.low, 2 * k + 1);
    for (int x = 0; x < w; ++x) odd[x] = Triangle(own[x], below[x]);
  }
}

void LowpassLuma(std::array<int, 2> factors, Workspace& ws) {
  if (factors[0] == 2) {
    for (int r = 0; r < ws.rows; ++r) LowpassAcross(ws.Row(ws.y, r), ws.width, ws.Row(ws.low, r), ws.Row(ws.scratch, r));
  } else {
    ws.low = ws.y;
  }
  if (factors[1] == 2) LowpassDown(ws);
}

// Sums over the 2 kWindowRadius + 1 samples around each of a row (edges repeated), of a[x] or of
// a[x] * b[x]. A running sum, in double: along thousands of samples a float one would drift.
void SumAcross(const float* a, const float* b, int width, float* out) {
  constexpr int r = kWindowRadius;
  const auto at = [&](int x) {
    const int i = std::clamp(x, 0, width - 1);
    return b ? double(a[i]) * b[i] : double(a[i]);
  };
  double sum = 0;
  for (int d = -r; d <= r; ++d) sum += at(d);
  for (int x = 0; x < width; ++x) {
    out[x] = float(sum);
    sum += at(x + r + 1) - at(x - r);
  }
}

// ws.means over the (2 kWindowRadius + 1)^2 window, for the band's rows [out_first, out_last).
void WindowMeans(int out_first, int out_last, Workspace& ws) {
  constexpr int r = kWindowRadius;
  constexpr float kInverse = 1.0f / float((2 * r + 1) * (2 * r + 1));
  const int w = ws.width, first = std::max(0, out_first - r), last = std::min(ws.rows, out_last + r);
  const std::pair<std::vector<float>*, std::vector<float>*> terms[kMeans] = {
      {&ws.low, nullptr}, {&ws.low, &ws.low}, {&ws.cb, nullptr}, {&ws.low, &ws.cb}, {&ws.cr, nullptr}, {&ws.low, &ws.cr}};
  for (int m = 0; m < kMeans; ++m) {
    for (int row = first; row < last; ++row)
      SumAcross(ws.Row(*terms[m].first, row), terms[m].second ? ws.Row(*terms[m].second, row) : nullptr, w,
                ws.Row(ws.across[m], row));
    for (int row = out_first; row < out_last; ++row) {
      float* dst = ws.Row(ws.means[m], row);
      const float* rows[2 * r + 1];
      for (int d = -r; d <= r; ++d) rows[d + r] = ws.Row(ws.across[m], std::clamp(row + d, 0, ws.rows - 1));
      for (int x = 0; x < w; ++x) {
        float sum = 0;
        for (const float* src : rows) sum += src[x];
        dst[x] = sum * kInverse;
      }
    }
  }
}

// sRGB-encoded value to linear, from a table of 4096 segments (within 1e-7 of SrgbToLinear).
class LinearTable {
 public:
  LinearTable() {
    for (int i = 0; i <= kSegments; ++i) table_[i] = SrgbToLinear(float(i) / kSegments);
  }
  float operator()(float v) const {
    const float at = std::clamp(v, 0.0f, 1.0f) * kSegments;
    const int i = std::min(int(at), kSegments - 1);
    return table_[i] + (at - float(i)) * (table_[i + 1] - table_[i]);
  }

 private:
  static constexpr int kSegments = 4096;
  float table_[kSegments + 1];
};

// The result's pixels in `band` (its y0 even) from the band of pixels around them.
void RestoreBand(const ImageU8& srgb, std::array<int, 2> factors, const PixelRect& band, const LinearTable& linear,
                 Image* out) {
  thread_local Workspace ws;
  const int first = std::max(0, band.y0 - kHalo), last = std::min(srgb.height(), band.y1 + kHalo);
  const int first_column = std::max(0, band.x0 - kHalo) & ~1, last_column = std::min(srgb.width(), band.x1 + kHalo);
  ws.Resize(last_column - first_column, last - first);
  ToYCbCr(srgb, first, first_column, ws);
  LowpassLuma(factors, ws);
  const int out_first = band.y0 - first, out_last = band.y1 - first;
  WindowMeans(out_first, out_last, ws);
  for (int r = out_first; r < out_last; ++r) {
    const float *y = ws.Row(ws.y, r), *low = ws.Row(ws.low, r), *cb = ws.Row(ws.cb, r), *cr = ws.Row(ws.cr, r);
    const float *m_low = ws.Row(ws.means[kLow], r), *m_low2 = ws.Row(ws.means[kLow2], r);
    const float *m_cb = ws.Row(ws.means[kCb], r), *m_low_cb = ws.Row(ws.means[kLowCb], r);
    const float *m_cr = ws.Row(ws.means[kCr], r), *m_low_cr = ws.Row(ws.means[kLowCr], r);
    float* dst = out->row(first + r) + 3 * size_t(first_column);
    for (int x = band.x0 - first_column; x < band.x1 - first_column; ++x) {
      // The chroma's missing detail: the luma's, times the local slope of chroma against luma.
      const float variance = std::max(0.0f, m_low2[x] - m_low[x] * m_low[x]);
      const float detail = (y[x] - low[x]) / (variance + kEps);
      const float blue_difference = cb[x] + (m_low_cb[x] - m_low[x] * m_cb[x]) * detail;
      const float red_difference = cr[x] + (m_low_cr[x] - m_low[x] * m_cr[x]) * detail;
      const float red = y[x] + 1.402f * red_difference, blue = y[x] + 1.772f * blue_difference;
      const float green = (y[x] - 0.299f * red - 0.114f * blue) * (1 / 0.587f);
      dst[3 * x] = linear(red), dst[3 * x + 1] = linear(green), dst[3 * x + 2] = linear(blue);
    }
  }
}

}  // namespace

bool ChromaDetailRestorable(std::array<int, 2> chroma_factors) {
  const auto supported = [](int f) { return f == 1 || f == 2; };
  return supported(chroma_factors[0]) && supported(chroma_factors[1]) && chroma_factors != std::array<int, 2>{1, 1};
}

Image LinearWithChromaDetail(const ImageU8& srgb, std::array<int, 2> chroma_factors, int band_rows,
                             std::span<const PixelRect> only) {
  MESOCAP_CHECK(srgb.channels() == 3, "LinearWithChromaDetail needs 3 channels");
  Image out = Image::Uninitialized(srgb.width(), srgb.height(), 3);
  const bool restorable = ChromaDetailRestorable(chroma_factors);
  if (!restorable || !only.empty()) {
    const auto& linear = SrgbDecodeTable();
    for (size_t i = 0; i < srgb.size(); ++i) out.data()[i] = linear[srgb.data()[i]];
  }
  if (!restorable) return out;
  MESOCAP_CHECK(band_rows > 0 && band_rows % 2 == 0, "bands must start chroma pairs");
  static const LinearTable linear;
  const PixelRect whole{0, 0, srgb.width(), srgb.height()};
  if (only.empty()) only = std::span<const PixelRect>(&whole, 1);
  // Each band of rows restores the union of the rectangles' columns across it: pieces that do not
  // overlap (threads never write the same pixel), at most a band's rows beyond a rectangle.
  std::vector<PixelRect> pieces;
  for (int y = 0; y < whole.y1; y += band_rows) {
    const int y_end = std::min(whole.y1, y + band_rows);
    std::vector<std::pair<int, int>> columns;
    for (const PixelRect& r : only)
      if (r.y0 < y_end && r.y1 > y && std::max(r.x0, 0) < std::min(r.x1, whole.x1))
        columns.push_back({std::max(r.x0, 0), std::min(r.x1, whole.x1)});
    std::sort(columns.begin(), columns.end());
    for (size_t k = 0; k < columns.size(); ++k) {
      if (!pieces.empty() && pieces.back().y0 == y && columns[k].first <= pieces.back().x1)
        pieces.back().x1 = std::max(pieces.back().x1, columns[k].second);
      else
        pieces.push_back({columns[k].first, y, columns[k].second, y_end});
    }
  }
  ParallelFor(0, int(pieces.size()), [&](int p) { RestoreBand(srgb, chroma_factors, pieces[p], linear, &out); });
  return out;
}

}  // namespace mesocap

#include "formats/ptm_file.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "core/atomic_file.h"
#include "core/parallel.h"
#include "formats/ptm_quantize.h"

namespace mesocap {
namespace fs = std::filesystem;

namespace {

constexpr const char* kMagic = "PTM_1.2";
constexpr const char* kLrgbName = "PTM_FORMAT_LRGB";
constexpr const char* kRgbName = "PTM_FORMAT_RGB";
constexpr double kFileUnits = 255.0;  // file coefficient = 255 * Ptm coefficient
constexpr int kMaxSide = 1 << 20;


// round-half-even (the default rounding mode, as std::nearbyint) and clamp to a byte. SSE2's
// cvtsd2si rounds in that mode and is inlined; nearbyint is a libm call on baseline x86-64.
// Clamping to [-1, 256] first keeps the conversion in range and changes no result.
inline unsigned char QuantizeByte(double value_over_step_plus_bias) {
  const double v = std::clamp(value_over_step_plus_bias, -1.0, 256.0);
#if defined(__SSE2__)
  const int r = _mm_cvtsd_si32(_mm_set_sd(v));
#else
  const int r = int(std::nearbyint(v));
#endif
  return static_cast<unsigned char>(std::clamp(r, 0, 255));
}

std::string Quote(std::string_view text) {
  std::string out = "'";
  for (char c : text.substr(0, 40)) out += (c >= 32 && c < 127) ? c : '?';
  if (text.size() > 40) out += "...";
  return out + "'";
}

// Reads header tokens from the start of a file's bytes without touching the binary payload
// beyond the header.
class HeaderReader {
 public:
  explicit HeaderReader(std::string_view bytes) : bytes_(bytes) {}

  // One line (up to '\n', a trailing '\r' and spaces removed); false at end of data.
  bool Line(std::string* line) {
    const size_t end = bytes_.find('\n', pos_);
    if (end == std::string_view::npos || end - pos_ > 256) return false;
    std::string_view text = bytes_.substr(pos_, end - pos_);
    while (!text.empty() && (text.back() == '\r' || text.back() == ' ' || text.back() == '\t'))
      text.remove_suffix(1);
    *line = std::string(text);
    pos_ = end + 1;
    return true;
  }

  // The next whitespace-separated token (spaces, tabs, CR, LF); false at end of data.
  bool Token(std::string* token) {
    while (pos_ < bytes_.size() && IsSpace(bytes_[pos_])) ++pos_;
    const size_t start = pos_;
    while (pos_ < bytes_.size() && !IsSpace(bytes_[pos_]) && pos_ - start < 64) ++pos_;
    if (pos_ == start) return false;
    *token = std::string(bytes_.substr(start, pos_ - start));
    return true;
  }

  // Skips spaces, tabs and CR up to and including the newline that ends the header.
  bool EndOfHeader() {
    while (pos_ < bytes_.size() &&
           (bytes_[pos_] == ' ' || bytes_[pos_] == '\t' || bytes_[pos_] == '\r'))
      ++pos_;
    if (pos_ >= bytes_.size() || bytes_[pos_] != '\n') return false;
    ++pos_;
    return true;
  }

  size_t position() const { return pos_; }

 private:
  static bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }
  std::string_view bytes_;
  size_t pos_ = 0;
};

bool ParseInt(const std::string& token, long* value) {
  errno = 0;
  char* end = nullptr;
  const long v = std::strtol(token.c_str(), &end, 10);
  if (errno != 0 || end == token.c_str() || *end != '\0') return false;
  *value = v;
  return true;
}

bool ParseFloat(const std::string& token, float* value) {
  errno = 0;
  char* end = nullptr;
  const float v = std::strtof(token.c_str(), &end);
  if (errno != 0 || end == token.c_str() || *end != '\0' || !std::isfinite(v)) return false;
  *value = v;
  return true;
}

// Relighting sums six coefficients times terms of magnitude <= 1 and a colour: decoded values
// beyond this (in file units) would overflow float arithmetic into inf and NaN.
constexpr double kMaxDecodedCoefficient = 1e30;

// The first coefficient index whose bytes 0..255 decode outside +-kMaxDecodedCoefficient, or -1.
int FirstUnboundedCoefficient(const PtmQuantization& q) {
  for (int k = 0; k < 6; ++k) {
    const double reach = std::max(std::abs(double(q.bias[k])), std::abs(255.0 - q.bias[k])) *
                         std::abs(double(q.scale[k]));
    if (!(reach <= kMaxDecodedCoefficient)) return k;
  }
  return -1;
}

}  // namespace

namespace {

// The range and finiteness of every coefficient, rows in parallel; `rows_out`, if given,
// receives each row's.
CoefficientRange RangeOf(const Ptm& ptm, std::vector<CoefficientRange>* rows_out = nullptr) {
  std::vector<CoefficientRange> ranges(size_t(ptm.height()));
  const int count = ptm.width() * ptm.coefficients.channels();
  ParallelFor(0, ptm.height(), [&](int y) { ranges[size_t(y)] = RowCoefficientRange(ptm.coefficients.row(y), count); });
  CoefficientRange all = CoefficientRange::Empty();
  for (const CoefficientRange& r : ranges) all.Include(r);
  if (rows_out) *rows_out = std::move(ranges);
  return all;
}

// The quantisation for a (finite) range.
PtmQuantization QuantizationFor(const CoefficientRange& range, bool integer_scales) {
  // In file units: 255 * the float's min is exactly the min of 255 * each (an exact product).
  std::array<double, 6> lo, hi;
  for (int k = 0; k < 6; ++k) lo[k] = kFileUnits * range.lo[k], hi[k] = kFileUnits * range.hi[k];
  PtmQuantization q;
  for (int k = 0; k < 6; ++k) {
    // Byte 0 decodes to -bias * scale and byte 255 to (255 - bias) * scale: find the bias whose
    // smallest covering scale is smallest. Every integer bias is tried, so a range that is
    // nearly all positive (or negative) still gets the finest step.
    const double m = std::min(lo[k], 0.0), big = std::max(hi[k], 0.0);
    double best_scale = std::numeric_limits<double>::infinity();
    int best_bias = 0;
    for (int b = 0; b <= 255; ++b) {
      if (m < 0 && b == 0) continue;
      if (big > 0 && b == 255) continue;
      const double s = std::max(m < 0 ? -m / b : 0.0, big > 0 ? big / (255 - b) : 0.0);
      if (s < best_scale) best_scale = s, best_bias = b;
    }
    if (!(best_scale > 0)) best_scale = 1.0;  // an all-zero coefficient: any scale will do
    if (integer_scales) {
      // The smallest whole-number scale with a bias that covers the range; the bias is put in
      // the middle of the feasible ones.
      for (double s = std::max(1.0, std::ceil(best_scale - 1e-9));; s += 1.0) {
        const double b_min = std::max(0.0, std::ceil(-m / s - 1e-12));
        const double b_max = 255.0 - std::max(0.0, std::ceil(big / s - 1e-12));
        if (b_min <= b_max) {
          q.scale[k] = float(s);
          q.bias[k] = int(b_min + std::floor((b_max - b_min) / 2));
          break;
        }
      }
      continue;
    }
    // The scale is stored as a float and printed with 9 significant digits (which round-trip):
    // round it up so the decoded range still covers [lo, hi].
    float s = float(best_scale);
    while (double(s) < best_scale) s = std::nextafter(s, std::numeric_limits<float>::infinity());
    s = std::nextafter(s, std::numeric_limits<float>::infinity());
    q.scale[k] = s;
    q.bias[k] = best_bias;
  }
  return q;
}

std::string PtmHeader(const PtmRowSource& rows, const PtmQuantization& q) {
  std::ostringstream header;
  header << kMagic << '\n' << (rows.format == PtmFormat::kLrgb ? kLrgbName : kRgbName) << '\n' << rows.width << '\n'
         << rows.height << '\n';
  char buf[64];
  for (int k = 0; k < 6; ++k) {
    std::snprintf(buf, sizeof buf, "%.9g", double(q.scale[k]));
    header << buf << (k < 5 ? ' ' : '\n');
  }
  for (int k = 0; k < 6; ++k) header << q.bias[k] << (k < 5 ? ' ' : '\n');
  return header.str();
}

}  // namespace

PtmQuantization ChoosePtmQuantization(const Ptm& ptm, bool integer_scales) {
  MESOCAP_CHECK(ptm.IsConsistent(), "inconsistent Ptm");
  return QuantizationFor(RangeOf(ptm), integer_scales);
}

Status WritePtmFile(const fs::path& path, const Ptm& ptm, const PtmWriteOptions& options,
                    PtmQuantization* quantization) {
  if (!ptm.IsConsistent())
    return Status::Error(path.string() +
                         ": cannot write PTM: coefficient and colour images do not match "
                         "the format");
  std::vector<CoefficientRange> row_ranges;
  PtmRowSource rows{ptm.format, ptm.width(), ptm.height(), RangeOf(ptm, &row_ranges), {}, {}};
  if (!rows.range.finite) {
    // The first non-finite coefficient in file order, for the message.
    int y = 0;
    while (row_ranges[size_t(y)].finite) ++y;
    const float* row = ptm.coefficients.row(y);
    const int per_pixel = ptm.coefficients.channels();
    int x = 0;
    while (x < ptm.width() * per_pixel && std::isfinite(row[x])) ++x;
    return Status::Error(path.string() + ": cannot write PTM: non-finite coefficient at pixel (" +
                         std::to_string(x / per_pixel) + ", " + std::to_string(y) + ")");
  }
  rows.coefficients = [&](int y, std::vector<float>*) -> StatusOr<const float*> { return ptm.coefficients.row(y); };
  rows.rgb = [&](int y, std::vector<float>*) -> StatusOr<const float*> { return ptm.rgb.row(y); };
  return WritePtmFile(path, rows, options, quantization);
}

Status WritePtmFile(const fs::path& path, const PtmRowSource& rows, const PtmWriteOptions& options,
                    PtmQuantization* quantization) {
  if (!rows.range.finite) return Status::Error(path.string() + ": cannot write PTM: non-finite coefficients");
  const int w = rows.width, h = rows.height;
  const PtmQuantization q = QuantizationFor(rows.range, options.integer_scales);
  const bool lrgb = rows.format == PtmFormat::kLrgb;
  const std::string header = PtmHeader(rows, q);
  double inv_scale[6];
  for (int k = 0; k < 6; ++k) inv_scale[k] = 1.0 / double(q.scale[k]);
  // The file after the header: one block per polynomial (LRGB: one; RGB: red, green, blue) of
  // 6 bytes per pixel, then for LRGB a block of 3 colour bytes per pixel; in each block, rows run
  // bottom to top.
  const int polynomials = lrgb ? 1 : 3, blocks = polynomials + (lrgb ? 1 : 0), per_pixel = 6 * polynomials;
  auto row_bytes = [&](int block) { return size_t(w) * (block < polynomials ? 6 : 3); };
  auto block_offset = [&](int block) { return header.size() + size_t(block) * size_t(h) * size_t(w) * 6; };
  // Bands of rows in parallel, each quantised into small per-thread buffers (every block of a row
  // from one read of its coefficients: the RGB blocks interleave in memory) and written at its
  // offsets, its write-back to disk started at once. A band's rows are contiguous in each block,
  // reversed. No buffer grows with the image: fresh memory costs page faults.
  const int band_rows = int(std::clamp<size_t>((size_t(256) << 10) / (size_t(w) * 6), 1, 64));
  const int bands = (h + band_rows - 1) / band_rows;
  MESOCAP_RETURN_IF_ERROR(WriteFileAtomically(path, [&](const fs::path& temp) -> Status {
    OutputFile file(temp);
    if (!file.ok()) return Status::Error(path.string() + ": cannot create: " + std::strerror(errno));
    file.WriteAt(0, header.data(), header.size());
    std::vector<Status> errors(size_t(bands), Status::Ok());
    ParallelFor(0, bands, [&](int band) {
      thread_local std::vector<unsigned char> buffers[4];
      thread_local std::vector<float> scratch;
      const int y0 = band * band_rows, count = std::min(band_rows, h - y0);
      for (int block = 0; block < blocks; ++block) buffers[block].resize(size_t(band_rows) * row_bytes(block));
      for (int r = 0; r < count; ++r) {
        const size_t slot = size_t(count - 1 - r);  // file rows run bottom to top
        StatusOr<const float*> coefficients = rows.coefficients(y0 + r, &scratch);
        if (!coefficients.ok()) return void(errors[size_t(band)] = coefficients.status());
        for (int block = 0; block < polynomials; ++block)
          QuantizeCoefficients(*coefficients + block * kPtmCoefficients, per_pixel, w, inv_scale, q.bias.data(),
                               buffers[block].data() + slot * row_bytes(block));
        if (!lrgb) continue;
        StatusOr<const float*> rgb = rows.rgb(y0 + r, &scratch);
        if (!rgb.ok()) return void(errors[size_t(band)] = rgb.status());
        unsigned char* dst = buffers[polynomials].data() + slot * row_bytes(polynomials);
        for (int i = 0; i < 3 * w; ++i) dst[i] = QuantizeByte(kFileUnits * (*rgb)[i]);
      }
      const size_t first_file_row = size_t(h - y0 - count);
      for (int block = 0; block < blocks; ++block) {
        const size_t offset = block_offset(block) + first_file_row * row_bytes(block);
        file.WriteAt(offset, buffers[block].data(), size_t(count) * row_bytes(block));
        file.StartWriteBack(offset, size_t(count) * row_bytes(block));
      }
    });
    for (const Status& error : errors) MESOCAP_RETURN_IF_ERROR(error);
    return file.Close() ? Status::Ok() : Status::Error(path.string() + ": write failed: " + std::strerror(errno));
  }));
  if (quantization) *quantization = q;
  return Status::Ok();
}

StatusOr<Ptm> ReadPtmFile(const fs::path& path, PtmQuantization* quantization) {
  const std::string name = path.string();
  auto read = ReadTextFile(path);
  if (!read.ok()) return read.status();
  const std::string bytes = std::move(*read);
  HeaderReader reader(bytes);
  std::string line;
  if (!reader.Line(&line) || line != kMagic)
    return Status::Error(name + ": not a PTM 1.2 file: the first line must be PTM_1.2" +
                         (bytes.empty() ? std::string(" (the file is empty)")
                                        : ", found " + Quote(bytes.substr(0, bytes.find('\n')))));
  if (!reader.Line(&line)) return Status::Error(name + ": truncated PTM header: no format line");
  PtmFormat format;
  if (line == kLrgbName)
    format = PtmFormat::kLrgb;
  else if (line == kRgbName)
    format = PtmFormat::kRgb;
  else if (line.rfind("PTM_FORMAT_", 0) == 0)
    return Status::Error(name + ": unsupported PTM format " + Quote(line) +
                         " (only PTM_FORMAT_LRGB and PTM_FORMAT_RGB are read)");
  else
    return Status::Error(name + ": malformed PTM header: " + Quote(line) +
                         " is not a PTM format name");

  std::string token;
  long size[2];
  const char* size_names[2] = {"width", "height"};
  for (int i = 0; i < 2; ++i) {
    if (!reader.Token(&token))
      return Status::Error(name + ": truncated PTM header: no " + size_names[i]);
    if (!ParseInt(token, &size[i]) || size[i] <= 0 || size[i] > kMaxSide)
      return Status::Error(name + ": malformed PTM header: " + size_names[i] + " " + Quote(token) +
                           " is not an integer in [1, " + std::to_string(kMaxSide) + "]");
  }
  PtmQuantization q;
  for (int k = 0; k < 6; ++k) {
    if (!reader.Token(&token))
      return Status::Error(name + ": truncated PTM header: " + std::to_string(k) + " of 6 scales");
    if (!ParseFloat(token, &q.scale[k]))
      return Status::Error(name + ": malformed PTM header: scale " + std::to_string(k) + " " +
                           Quote(token) + " is not a finite number");
  }
  for (int k = 0; k < 6; ++k) {
    long bias;
    if (!reader.Token(&token))
      return Status::Error(name + ": truncated PTM header: " + std::to_string(k) + " of 6 biases");
    if (!ParseInt(token, &bias) || bias < -65536 || bias > 65536)
      return Status::Error(name + ": malformed PTM header: bias " + std::to_string(k) + " " +
                           Quote(token) + " is not an integer");
    q.bias[k] = int(bias);
  }
  if (!reader.EndOfHeader())
    return Status::Error(name +
                         ": malformed PTM header: the line of biases must end with a newline");
  if (const int k = FirstUnboundedCoefficient(q); k >= 0)
    return Status::Error(name + ": malformed PTM header: scale " + std::to_string(k) + " " +
                         Quote(std::to_string(q.scale[k])) + " with bias " + std::to_string(q.bias[k]) +
                         " decodes to coefficients beyond " + Quote(std::to_string(kMaxDecodedCoefficient)));

  const int w = int(size[0]), h = int(size[1]);
  const size_t pixels = size_t(w) * size_t(h);
  const bool lrgb = format == PtmFormat::kLrgb;
  const size_t expected = lrgb ? pixels * 9 : pixels * 18;
  const size_t found = bytes.size() - reader.position();
  if (found < expected)
    return Status::Error(name + ": truncated PTM file: a " + std::to_string(w) + "x" +
                         std::to_string(h) + " " + (lrgb ? kLrgbName : kRgbName) + " needs " +
                         std::to_string(expected) + " bytes after the header, found " +
                         std::to_string(found));
  if (found > expected)
    return Status::Error(name + ": malformed PTM file: " + std::to_string(found - expected) +
                         " unexpected bytes after the " + std::to_string(expected) +
                         " bytes of pixel data");

  Ptm ptm;
  ptm.format = format;
  ptm.coefficients = Image(w, h, lrgb ? kPtmCoefficients : 3 * kPtmCoefficients);
  if (lrgb) ptm.rgb = Image(w, h, 3);
  const unsigned char* src =
      reinterpret_cast<const unsigned char*>(bytes.data()) + reader.position();
  float step[6];
  for (int k = 0; k < 6; ++k) step[k] = float(double(q.scale[k]) / kFileUnits);
  for (int c = 0; c < ptm.polynomials(); ++c) {
    for (int row = 0; row < h; ++row) {
      const int y = h - 1 - row;
      for (int x = 0; x < w; ++x) {
        float* a = ptm.coefficients.pixel(x, y) + c * kPtmCoefficients;
        for (int k = 0; k < 6; ++k) a[k] = float(int(*src++) - q.bias[k]) * step[k];
      }
    }
  }
  if (lrgb) {
    for (int row = 0; row < h; ++row) {
      float* rgb = ptm.rgb.row(h - 1 - row);
      for (int i = 0; i < w * 3; ++i) rgb[i] = float(*src++) / float(kFileUnits);
    }
  }
  if (quantization) *quantization = q;
  return ptm;
}

}  // namespace mesocap

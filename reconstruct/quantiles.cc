#include "reconstruct/quantiles.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

namespace mesocap {
namespace {

// Below this many values std::sort beats the radix sort's histogram passes.
constexpr size_t kRadixSortMin = 1024;

// Maps a float to an unsigned key with the same order (negative floats reversed, sign flipped).
inline uint32_t OrderedKey(float value) {
  uint32_t bits;
  std::memcpy(&bits, &value, sizeof(bits));
  return (bits & 0x80000000u) ? ~bits : (bits | 0x80000000u);
}

inline float KeyToFloat(uint32_t key) {
  const uint32_t bits = (key & 0x80000000u) ? (key & 0x7fffffffu) : ~key;
  float value;
  std::memcpy(&value, &bits, sizeof(value));
  return value;
}

// Stable LSD radix sort of `items` by the 32 bits starting at bit `key_shift`, 11-bit digits
// (skipping digits every item shares). `scratch` is resized as needed.
template <typename T>
void RadixSort(std::vector<T>* items, std::vector<T>* scratch, int key_shift) {
  constexpr int kBits = 11, kBuckets = 1 << kBits, kPasses = 3;  // 11 + 11 + 10 bits
  const size_t n = items->size();
  scratch->resize(n);
  uint32_t counts[kPasses][kBuckets] = {};
  for (const T item : *items) {
    const uint32_t key = uint32_t(item >> key_shift);
    for (int p = 0; p < kPasses; ++p) ++counts[p][(key >> (p * kBits)) & (kBuckets - 1)];
  }
  T* src = items->data();
  T* dst = scratch->data();
  for (int p = 0; p < kPasses; ++p) {
    uint32_t* count = counts[p];
    const int shift = key_shift + p * kBits;
    if (count[(uint32_t(src[0] >> key_shift) >> (p * kBits)) & (kBuckets - 1)] == n) continue;  // one bucket
    uint32_t offset = 0;
    for (int b = 0; b < kBuckets; ++b) {
      const uint32_t c = count[b];
      count[b] = offset;
      offset += c;
    }
    for (size_t i = 0; i < n; ++i) dst[count[(src[i] >> shift) & (kBuckets - 1)]++] = src[i];
    std::swap(src, dst);
  }
  if (src != items->data()) items->swap(*scratch);
}

// The values of `samples` in increasing order.
std::vector<float> Sorted(std::span<const float> samples) {
  if (samples.size() < kRadixSortMin) {
    std::vector<float> sorted(samples.begin(), samples.end());
    std::sort(sorted.begin(), sorted.end());
    return sorted;
  }
  std::vector<uint32_t> keys(samples.size()), scratch;
  for (size_t i = 0; i < samples.size(); ++i) keys[i] = OrderedKey(samples[i]);
  RadixSort(&keys, &scratch, 0);
  std::vector<float> sorted(keys.size());
  for (size_t i = 0; i < keys.size(); ++i) sorted[i] = KeyToFloat(keys[i]);
  return sorted;
}

// Q at position x in sample units (x in [0, n-1]), linear between samples.
inline float Interpolate(const float* q, size_t n, double x) {
  if (x <= 0) return q[0];
  const double last = double(n - 1);
  if (x >= last) return q[n - 1];
  const size_t i = size_t(x);
  const double t = x - double(i);
  return float(q[i] + (double(q[i + 1]) - q[i]) * t);
}

// Integral of |d| over [0, h] for d linear from d0 to d1.
inline double AbsIntegral(double d0, double d1, double h) {
  if ((d0 >= 0) == (d1 >= 0)) return 0.5 * std::abs(d0 + d1) * h;
  const double a = std::abs(d0), b = std::abs(d1);
  return 0.5 * (a * a + b * b) / (a + b) * h;  // the zero crossing splits two triangles
}

}  // namespace

float InverseCdf::At(double p) const {
  if (values.empty()) throw std::invalid_argument("InverseCdf::At on an empty distribution");
  if (values.size() == 1) return values[0];
  return Interpolate(values.data(), values.size(), std::clamp(p, 0.0, 1.0) * double(values.size() - 1));
}

double InverseCdf::Mean() const {
  if (values.empty()) throw std::invalid_argument("InverseCdf::Mean of an empty distribution");
  if (values.size() == 1) return values[0];
  double sum = 0.5 * (double(values.front()) + values.back());
  for (size_t k = 1; k + 1 < values.size(); ++k) sum += values[k];
  return sum / double(values.size() - 1);
}

InverseCdf InverseCdfOf(std::span<const float> samples, int count) {
  if (samples.empty()) throw std::invalid_argument("InverseCdfOf: no samples");
  if (count < 2) throw std::invalid_argument("InverseCdfOf: count " + std::to_string(count) + " < 2");
  const std::vector<float> sorted = Sorted(samples);
  InverseCdf q;
  q.values.resize(count);
  const double step = double(sorted.size() - 1) / double(count - 1);
  for (int k = 0; k < count; ++k) q.values[k] = Interpolate(sorted.data(), sorted.size(), k * step);
  q.values.back() = sorted.back();  // exact maximum despite round-off in k * step
  return q;
}

InverseCdf BlendInverseCdfs(std::span<const InverseCdf* const> cdfs, std::span<const double> weights) {
  return BlendInverseCdfs(cdfs, weights, {});
}

InverseCdf BlendInverseCdfs(std::span<const InverseCdf* const> cdfs, std::span<const double> weights,
                            std::span<const char> negated) {
  if (!negated.empty() && negated.size() != cdfs.size())
    throw std::invalid_argument("BlendInverseCdfs: " + std::to_string(cdfs.size()) + " distributions, " +
                                std::to_string(negated.size()) + " negation flags");
  if (cdfs.empty() || cdfs.size() != weights.size())
    throw std::invalid_argument("BlendInverseCdfs: " + std::to_string(cdfs.size()) + " distributions, " +
                                std::to_string(weights.size()) + " weights");
  const size_t n = cdfs[0]->values.size();
  if (n == 0) throw std::invalid_argument("BlendInverseCdfs: empty distribution");
  for (const InverseCdf* q : cdfs)
    if (q->values.size() != n) throw std::invalid_argument("BlendInverseCdfs: distributions of different lengths");
  std::vector<double> sum(n, 0.0);
  for (size_t i = 0; i < cdfs.size(); ++i) {
    const double w = weights[i];
    const float* v = cdfs[i]->values.data();
    if (!negated.empty() && negated[i]) {
      for (size_t k = 0; k < n; ++k) sum[k] -= w * v[n - 1 - k];
    } else {
      for (size_t k = 0; k < n; ++k) sum[k] += w * v[k];
    }
  }
  InverseCdf out;
  out.values.resize(n);
  float running = float(sum[0]);
  for (size_t k = 0; k < n; ++k) {
    running = std::max(running, float(sum[k]));
    out.values[k] = running;
  }
  return out;
}

void MatchToInverseCdf(std::span<float> values, const InverseCdf& target) {
  if (target.empty()) throw std::invalid_argument("MatchToInverseCdf: empty target distribution");
  const size_t n = values.size();
  if (n == 0) return;
  if (n > UINT32_MAX) throw std::invalid_argument("MatchToInverseCdf: too many values");
  // (key << 32 | index): sorting these orders by value, ties by index.
  std::vector<uint64_t> order(n), scratch;
  for (size_t i = 0; i < n; ++i) order[i] = (uint64_t(OrderedKey(values[i])) << 32) | uint64_t(i);
  if (n < kRadixSortMin) {
    std::sort(order.begin(), order.end());
  } else {
    RadixSort(&order, &scratch, 32);  // stable, and indices start ascending
  }
  const float* q = target.values.data();
  const size_t m = target.values.size();
  const double scale = m > 1 ? double(m - 1) / double(n) : 0.0;
  for (size_t r = 0; r < n; ++r)
    values[uint32_t(order[r])] = m > 1 ? Interpolate(q, m, (double(r) + 0.5) * scale) : q[0];
}

double WassersteinDistance(const InverseCdf& a, const InverseCdf& b) {
  if (a.empty() || b.empty()) throw std::invalid_argument("WassersteinDistance: empty distribution");
  const size_t na = a.values.size(), nb = b.values.size();
  if (na == 1 && nb == 1) return std::abs(double(a.values[0]) - b.values[0]);
  // Both are linear between the union of their sample positions, so the integral is exact.
  std::vector<double> p;
  p.reserve(na + nb);
  for (size_t k = 0; k < na; ++k) p.push_back(na > 1 ? double(k) / double(na - 1) : 0.0);
  for (size_t k = 0; k < nb; ++k) p.push_back(nb > 1 ? double(k) / double(nb - 1) : 0.0);
  p.push_back(1.0);
  std::sort(p.begin(), p.end());
  p.erase(std::unique(p.begin(), p.end()), p.end());
  double total = 0;
  double d_prev = double(a.At(p[0])) - b.At(p[0]);
  for (size_t i = 1; i < p.size(); ++i) {
    const double d = double(a.At(p[i])) - b.At(p[i]);
    total += AbsIntegral(d_prev, d, p[i] - p[i - 1]);
    d_prev = d;
  }
  return total;
}

}  // namespace mesocap

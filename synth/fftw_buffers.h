// FFTW's aligned buffers as owning types, shared by the FFT-based patch matching and the texton
// filter bank; both plan under core's FftwPlannerMutex.
#pragma once

#include <algorithm>
#include <complex>
#include <cstddef>
#include <mutex>
#include <utility>

#include <fftw3.h>

#include "core/fftw_planner.h"

namespace mesocap {

using FftComplex = std::complex<float>;

struct FftFloatBuffer {
  float* data = nullptr;
  explicit FftFloatBuffer(size_t n) : data(fftwf_alloc_real(n)) { std::fill_n(data, n, 0.f); }
  FftFloatBuffer(const FftFloatBuffer&) = delete;
  FftFloatBuffer& operator=(const FftFloatBuffer&) = delete;
  ~FftFloatBuffer() { fftwf_free(data); }
};

struct FftComplexBuffer {
  FftComplex* data = nullptr;
  size_t n = 0;
  explicit FftComplexBuffer(size_t count) : data(reinterpret_cast<FftComplex*>(fftwf_alloc_complex(count))), n(count) {
    std::fill_n(data, n, FftComplex(0));
  }
  FftComplexBuffer(FftComplexBuffer&& o) noexcept : data(o.data), n(o.n) { o.data = nullptr; }
  FftComplexBuffer& operator=(FftComplexBuffer&& o) noexcept {
    std::swap(data, o.data);
    std::swap(n, o.n);
    return *this;
  }
  ~FftComplexBuffer() { fftwf_free(data); }
  fftwf_complex* fftw() const { return reinterpret_cast<fftwf_complex*>(data); }
};

}  // namespace mesocap

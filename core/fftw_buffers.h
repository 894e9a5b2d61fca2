// FFTW's aligned buffers as owning types, and the plans of 2-D real FFTs, shared by every FFT user
// (the steerable pyramid, the capture blur's undoing, the texton filter bank, FFT patch matching).
#pragma once

#include <algorithm>
#include <complex>
#include <cstddef>
#include <new>
#include <utility>

#include <fftw3.h>

namespace mesocap {

using FftComplex = std::complex<float>;

struct FftFloatBuffer {
  float* data = nullptr;
  explicit FftFloatBuffer(size_t n) : data(fftwf_alloc_real(n)) {
    if (!data) throw std::bad_alloc();
    std::fill_n(data, n, 0.f);
  }
  FftFloatBuffer(const FftFloatBuffer&) = delete;
  FftFloatBuffer& operator=(const FftFloatBuffer&) = delete;
  ~FftFloatBuffer() { fftwf_free(data); }
};

struct FftComplexBuffer {
  FftComplex* data = nullptr;
  size_t n = 0;
  explicit FftComplexBuffer(size_t count) : data(reinterpret_cast<FftComplex*>(fftwf_alloc_complex(count))), n(count) {
    if (!data) throw std::bad_alloc();
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

// The forward (r2c) and inverse (c2r, unnormalised, destroys its input) plans of a 2-D real FFT of
// one size, out of place: planned once per process (FFTW_ESTIMATE, under the one lock around
// FFTW's planner, which is not thread-safe; executing a plan with the new-array functions is) and
// never destroyed, so threads still running at exit may execute them. Execute with
// fftwf_execute_dft_r2c and fftwf_execute_dft_c2r on arrays of FFTW's alignment (the buffers
// above, fftwf_alloc_*), as they were planned on. A spectrum has height rows of width / 2 + 1
// bins. Sizes are few (FFT-friendly sizes of slices, filter banks and patch matches), so the cache
// keeps every plan.
struct RealFftPlans {
  fftwf_plan forward = nullptr, inverse = nullptr;
};
const RealFftPlans& RealFftPlansFor(int width, int height);

// The least size >= n whose only prime factors are 2, 3 and 5, where FFTW stays fast.
int FftFriendlySize(int n);

}  // namespace mesocap

#include "core/fftw_buffers.h"

#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

namespace mesocap {

const RealFftPlans& RealFftPlansFor(int width, int height) {
  if (width <= 0 || height <= 0)
    throw std::invalid_argument("RealFftPlansFor: size " + std::to_string(width) + "x" + std::to_string(height));
  // Never destroyed: plans stay valid for threads still running at exit.
  static auto* plans = new std::map<std::pair<int, int>, std::unique_ptr<const RealFftPlans>>;
  // One lock around FFTW's planner for the whole process, whichever library plans (also never
  // destroyed).
  static auto* planner = new std::mutex;
  std::lock_guard<std::mutex> lock(*planner);
  auto& slot = (*plans)[{width, height}];
  if (!slot) {
    FftFloatBuffer real(size_t(width) * size_t(height));
    FftComplexBuffer spectrum(size_t(width / 2 + 1) * size_t(height));
    auto made = std::make_unique<RealFftPlans>();
    made->forward = fftwf_plan_dft_r2c_2d(height, width, real.data, spectrum.fftw(), FFTW_ESTIMATE);
    made->inverse = fftwf_plan_dft_c2r_2d(height, width, spectrum.fftw(), real.data, FFTW_ESTIMATE);
    if (!made->forward || !made->inverse) {
      if (made->forward) fftwf_destroy_plan(made->forward);
      if (made->inverse) fftwf_destroy_plan(made->inverse);
      throw std::runtime_error("FFTW could not plan a " + std::to_string(width) + "x" + std::to_string(height) +
                               " transform");
    }
    slot = std::move(made);
  }
  return *slot;
}

int FftFriendlySize(int n) {
  for (int m = std::max(n, 1);; ++m) {
    int r = m;
    for (int p : {2, 3, 5})
      while (r % p == 0) r /= p;
    if (r == 1) return m;
  }
}

}  // namespace mesocap

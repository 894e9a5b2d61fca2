#include "calib/tag_detection.h"

#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>

#include <algorithm>
#include <cmath>

namespace mesocap {
namespace {

// One tag36h11 detector per thread, made on first use: adding the family builds its decode table
// for 2-bit error correction (about 9 MB), which cost more than detecting in a board's crop, and a
// detector serves one image at a time.
class ThreadDetector {
 public:
  ThreadDetector() : family_(tag36h11_create()), detector_(apriltag_detector_create()) {
    apriltag_detector_add_family(detector_, family_);
    detector_->quad_decimate = 1.0f;
    detector_->nthreads = 1;  // callers parallelise over images
  }
  ~ThreadDetector() {
    apriltag_detector_destroy(detector_);
    tag36h11_destroy(family_);
  }
  ThreadDetector(const ThreadDetector&) = delete;
  ThreadDetector& operator=(const ThreadDetector&) = delete;
  static apriltag_detector_t* Get() {
    thread_local ThreadDetector detector;
    return detector.detector_;
  }

 private:
  apriltag_family_t* family_;
  apriltag_detector_t* detector_;
};

}  // namespace

std::vector<TagDetection> DetectTags(const Image& im, const TagDetectOptions& options) {
  // Linear luminance scaled so the bright end (not the mirror highlights) reaches 255: detecting
  // on sRGB-encoded values moves blurred edges toward white by about 0.2 px.
  const int W = im.width(), H = im.height();
  Image luminance = Luminance(im);
  float* lum = luminance.data();
  const size_t n = luminance.size();
  for (size_t i = 0; i < n; ++i) lum[i] = std::isfinite(lum[i]) && lum[i] > 0.0f ? lum[i] : 0.0f;  // an EXR may hold NaN, inf or negatives
  std::vector<float> sample;
  for (size_t i = 0; i < n; i += 97) sample.push_back(lum[i]);
  const size_t k = size_t(0.995 * (sample.size() - 1));
  std::nth_element(sample.begin(), sample.begin() + k, sample.end());
  const float scale = 255.0f / std::max(sample[k], 1e-6f);
  std::vector<uint8_t> buf(n);
  for (size_t i = 0; i < n; ++i) buf[i] = uint8_t(std::min(255.0f, std::round(lum[i] * scale)));

  // Debian's libapriltag exports no image_u8_create: the detector reads our buffer.
  image_u8_t gray{W, H, W, buf.data()};
  apriltag_detector_t* detector = ThreadDetector::Get();
  detector->quad_sigma = options.quad_sigma;
  zarray_t* found = apriltag_detector_detect(detector, &gray);
  std::vector<TagDetection> out;
  for (int i = 0; i < zarray_size(found); ++i) {
    apriltag_detection_t* det;
    zarray_get(found, i, &det);
    if (det->decision_margin < options.min_decision_margin) continue;
    TagDetection d;
    d.id = det->id;
    d.decision_margin = det->decision_margin;
    for (int c = 0; c < 4; ++c) d.corners_px[c] = {det->p[c][0] - 0.5, det->p[c][1] - 0.5};
    out.push_back(d);
  }
  apriltag_detections_destroy(found);
  std::sort(out.begin(), out.end(), [](const TagDetection& a, const TagDetection& b) { return a.id < b.id; });
  return out;
}

}  // namespace mesocap

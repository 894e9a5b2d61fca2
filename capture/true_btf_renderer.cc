#include "capture/true_btf_renderer.h"

#include <algorithm>

namespace mesocap {

TrueBtfRenderer::TrueBtfRenderer(const Material& material, const TrueBtfRequest& grid, size_t max_cached_bytes)
    : material_(material), grid_(grid) {
  const size_t samples = size_t(std::max(1, grid.samples_per_axis)) * std::max(1, grid.samples_per_axis);
  const size_t view_bytes = size_t(grid.size) * grid.size * samples * sizeof(MaterialHit);
  max_cached_views_ = std::max<size_t>(1, max_cached_bytes / std::max<size_t>(1, view_bytes));
}

std::shared_ptr<TrueBtfRenderer::TracedView> TrueBtfRenderer::HitsOf(const TrueBtfRequest& r,
                                                                     const TrueBtfFrame& frame) const {
  const ViewKey key{r.theta_o_deg, r.phi_o_deg};
  std::shared_ptr<TracedView> view;
  {
    std::lock_guard lock(mutex_);
    auto it = cache_.find(key);
    if (it != cache_.end()) {
      view = it->second;
      recency_.remove(key);
    } else {
      view = std::make_shared<TracedView>();
      cache_.emplace(key, view);
      if (cache_.size() > max_cached_views_) {  // an evicted view stays alive while a slice uses it
        cache_.erase(recency_.back());
        recency_.pop_back();
      }
    }
    recency_.push_front(key);
  }
  // Tracing outside the lock; a second thread asking for the same view waits for the first.
  std::call_once(view->traced, [&] {
    const int n = std::max(1, r.samples_per_axis);
    view->hits.resize(size_t(r.size) * r.size * n * n);
    MaterialHit* hit = view->hits.data();
    for (int j = 0; j < r.size; ++j)
      for (int i = 0; i < r.size; ++i)
        for (int sy = 0; sy < n; ++sy)
          for (int sx = 0; sx < n; ++sx) {
            const Eigen::Vector2d xy = TexelSamplePoint(r, frame, i, j, sx, sy);
            *hit++ = TraceFromViewer(material_, xy.x(), xy.y(), frame.wo);
          }
    std::lock_guard lock(mutex_);
    ++views_traced_;
  });
  return view;
}

Image TrueBtfRenderer::Render(const Eigen::Vector3d& light, const Eigen::Vector3d& view) const {
  TrueBtfRequest r = TrueBtfRequestFor(light, view, grid_.size, grid_.samples_per_axis);
  r.patch_m = grid_.patch_m;
  r.offset_m = grid_.offset_m;
  r.material_rotation_deg = grid_.material_rotation_deg;
  const TrueBtfFrame frame(r);
  const std::shared_ptr<TracedView> traced = HitsOf(r, frame);
  const int n = std::max(1, r.samples_per_axis);
  Image out(r.size, r.size, 3);
  const MaterialHit* hit = traced->hits.data();
  for (int j = 0; j < r.size; ++j)
    for (int i = 0; i < r.size; ++i) {
      Eigen::Vector3f L = Eigen::Vector3f::Zero();
      for (int s = 0; s < n * n; ++s) L += LitRadiance(material_, *hit++, frame.wi, frame.wo);
      L /= float(n * n);
      float* px = out.pixel(i, j);
      px[0] = L.x();
      px[1] = L.y();
      px[2] = L.z();
    }
  return out;
}

int TrueBtfRenderer::views_traced() const {
  std::lock_guard lock(mutex_);
  return views_traced_;
}

}  // namespace mesocap

// True BTF slices of one material on one texel grid, for work that renders many slices of few
// views (the evaluation renders each input view under 81 lights): a view's rays meet the height
// field at points that do not depend on the light, so each view is traced once and its hits are
// kept (recently used views first, up to a memory bound). The slices are RenderTrueBtfSlice's,
// to the bit.
#pragma once

#include <cstddef>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "capture/btf_render.h"

namespace mesocap {

class TrueBtfRenderer {
 public:
  // `grid`: the texel grid (size, samples_per_axis, patch_m, offset_m, material_rotation_deg);
  // its angles are ignored. The material must outlive the renderer.
  TrueBtfRenderer(const Material& material, const TrueBtfRequest& grid, size_t max_cached_bytes = size_t(256) << 20);

  // The slice under `light` seen from `view` (unit, patch frame). Thread-safe; serial inside, so
  // callers run slices in parallel.
  Image Render(const Eigen::Vector3d& light, const Eigen::Vector3d& view) const;

  int views_traced() const;  // how many times a view was traced (a view evicted and needed again counts twice)

 private:
  struct TracedView {
    std::once_flag traced;
    std::vector<MaterialHit> hits;  // texel-major (row j, column i), then sample (sy, sx)
  };
  using ViewKey = std::pair<double, double>;  // (theta_o, phi_o) in degrees, as the request holds them
  std::shared_ptr<TracedView> HitsOf(const TrueBtfRequest& request, const TrueBtfFrame& frame) const;

  const Material& material_;
  TrueBtfRequest grid_;
  size_t max_cached_views_;
  mutable std::mutex mutex_;
  mutable std::map<ViewKey, std::shared_ptr<TracedView>> cache_;
  mutable std::list<ViewKey> recency_;  // front: most recently used
  mutable int views_traced_ = 0;
};

}  // namespace mesocap

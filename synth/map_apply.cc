#include "synth/map_apply.h"

#include <atomic>
#include <cmath>
#include <list>
#include <map>
#include <mutex>

#include "core/directions.h"
#include "core/parallel.h"

namespace mesocap {

Eigen::Vector3d TurnDirection(const Eigen::Vector3d& d, double rotation_deg) {
  const double c = std::cos(DegToRad(rotation_deg)), s = std::sin(DegToRad(rotation_deg));
  return {c * d.x() + s * d.y(), -s * d.x() + c * d.y(), d.z()};  // turned by -rotation about z
}

StatusOr<SliceDirectionLookup> SliceDirectionLookup::Create(const std::vector<ExemplarSlice>& slices) {
  if (slices.empty()) return Status::Error("no slices to interpolate");
  SliceDirectionLookup lookup;
  lookup.slices_ = slices;
  for (int k = 0; k < int(slices.size()); ++k) {
    auto it = std::find_if(lookup.views_.begin(), lookup.views_.end(),
                           [&](const View& v) { return AngleBetweenDeg(v.direction, slices[k].view) < 0.5; });
    if (it == lookup.views_.end()) {
      lookup.views_.push_back({slices[k].view, {}, nullptr});
      it = lookup.views_.end() - 1;
    }
    it->slices.push_back(k);
  }
  std::vector<Eigen::Vector3d> view_directions;
  for (View& v : lookup.views_) {
    view_directions.push_back(v.direction);
    std::vector<Eigen::Vector3d> lights;
    for (int k : v.slices) lights.push_back(slices[k].light);
    auto interp = LightInterpolator::Create(lights);
    if (interp.ok()) v.lights = std::make_shared<LightInterpolator>(std::move(*interp));
  }
  if (lookup.views_.size() > 1) {
    auto rings = ViewInterpolator::Create(view_directions, 10.0, /*max_extrapolation=*/0.0);
    if (rings.ok()) lookup.view_rings_ = std::make_shared<ViewInterpolator>(std::move(*rings));
  }
  return lookup;
}

std::vector<WeightedIndex> SliceDirectionLookup::Weights(const Eigen::Vector3d& light, const Eigen::Vector3d& view) const {
  for (int k = 0; k < int(slices_.size()); ++k)  // a measured pair: exactly that slice
    if (AngleBetweenDeg(slices_[k].light, light) < 1e-4 && AngleBetweenDeg(slices_[k].view, view) < 1e-4) return {{k, 1.0}};
  std::vector<WeightedIndex> views;
  if (view_rings_) {
    views = view_rings_->Weights(view);
  } else {
    views = {{0, 1.0}};
  }
  auto nearest_view = std::min_element(views_.begin(), views_.end(), [&](const View& a, const View& b) {
    return AngleBetweenDeg(a.direction, view) < AngleBetweenDeg(b.direction, view);
  });
  if (AngleBetweenDeg(nearest_view->direction, view) < 0.5) views = {{int(nearest_view - views_.begin()), 1.0}};
  std::vector<WeightedIndex> out;
  for (const WeightedIndex& v : views) {
    const View& view_entry = views_[v.index];
    if (view_entry.lights) {
      for (const WeightedIndex& l : view_entry.lights->Weights(light)) out.push_back({view_entry.slices[l.index], v.weight * l.weight});
    } else {  // too few lights to triangulate: the nearest one
      int best = view_entry.slices[0];
      for (int k : view_entry.slices)
        if (AngleBetweenDeg(slices_[k].light, light) < AngleBetweenDeg(slices_[best].light, light)) best = k;
      out.push_back({best, v.weight});
    }
  }
  return MergeWeights(out);
}

namespace {

// Decoded sample slices shared by the workers, least recently used dropped first.
class SliceCache {
 public:
  SliceCache(const std::function<StatusOr<Image>(int)>& read, int capacity) : read_(read), capacity_(std::max(1, capacity)) {}
  StatusOr<std::shared_ptr<const Image>> Get(int k) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      auto it = entries_.find(k);
      if (it != entries_.end()) {
        order_.splice(order_.begin(), order_, it->second.second);
        return it->second.first;
      }
    }
    auto image = read_(k);
    if (!image.ok()) return image.status();
    auto shared = std::make_shared<const Image>(std::move(*image));
    std::lock_guard<std::mutex> lock(mutex_);
    if (entries_.count(k)) return entries_[k].first;
    order_.push_front(k);
    entries_[k] = {shared, order_.begin()};
    while (int(entries_.size()) > capacity_) {
      entries_.erase(order_.back());
      order_.pop_back();
    }
    return shared;
  }

 private:
  std::function<StatusOr<Image>(int)> read_;
  int capacity_;
  std::mutex mutex_;
  std::list<int> order_;
  std::map<int, std::pair<std::shared_ptr<const Image>, std::list<int>::iterator>> entries_;
};

}  // namespace

StatusOr<Image> SynthesizedSlice(const SynthMap& map, const SliceDirectionLookup& lookup,
                                 const ExemplarSlice& target, const std::function<StatusOr<Image>(int)>& read_slice) {
  // One source image per distinct rotation in the map.
  std::map<float, Image> sources;
  for (float r : map.rotation_deg) sources.emplace(r, Image());
  for (auto& [rotation, source] : sources) {
    const auto weights = lookup.Weights(TurnDirection(target.light, rotation), TurnDirection(target.view, rotation));
    for (const WeightedIndex& w : weights) {
      auto slice = read_slice(w.index);
      if (!slice.ok()) return slice.status();
      if (weights.size() == 1) {
        source = std::move(*slice);
        break;
      }
      if (source.empty()) source = Image(slice->width(), slice->height(), slice->channels());
      for (size_t i = 0; i < source.size(); ++i) source.data()[i] += float(w.weight) * slice->data()[i];
    }
  }
  Image out(map.width, map.height, 3);
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      const Image& source = sources.at(map.rotation_deg[map.index(x, y)]);
      const Eigen::Vector2i s = map.SourceTexel(x, y);
      std::copy_n(source.pixel(s.x(), s.y()), 3, out.pixel(x, y));
    }
  return out;
}

Status ApplyMapToBtf(const SynthMap& map, const Exemplar& exemplar, const std::vector<int>& slices,
                     const std::function<Status(int, const Image&)>& write, const ApplyOptions& options,
                     const ProgressFn& progress) {
  if (map.sample_width != exemplar.width || map.sample_height != exemplar.height)
    return Status::Error("the map points into a " + std::to_string(map.sample_width) + "x" + std::to_string(map.sample_height) +
                         " sample; the exemplar is " + std::to_string(exemplar.width) + "x" + std::to_string(exemplar.height));
  auto lookup = SliceDirectionLookup::Create(exemplar.slices);
  if (!lookup.ok()) return lookup.status();
  SliceCache cache([&](int k) { return exemplar.ReadSlice(k); }, options.cache_slices);
  auto read = [&](int k) -> StatusOr<Image> {
    auto s = cache.Get(k);
    if (!s.ok()) return s.status();
    return **s;
  };
  std::vector<Status> errors(slices.size());
  std::atomic<int> done = 0;
  std::atomic<bool> stop = false;
  ParallelFor(0, int(slices.size()), [&](int i) {
    if (stop) return;
    auto slice = SynthesizedSlice(map, *lookup, exemplar.slices[slices[i]], read);
    errors[i] = slice.ok() ? write(slices[i], *slice) : slice.status();
    if (!errors[i].ok() || !ReportProgress(progress, ++done, int(slices.size()), "applying the map")) stop = true;
  }, options.num_threads);
  for (const Status& e : errors)
    if (!e.ok()) return e;
  if (stop) return Status::Cancelled();
  return Status::Ok();
}

void RotatePtmCoefficients(const float* a, double rotation_deg, float* b) {
  // L_out(l) = L_sample(R(-r) l): lu' = c lu + s lv, lv' = -s lu + c lv.
  const double c = std::cos(DegToRad(rotation_deg)), s = std::sin(DegToRad(rotation_deg));
  b[0] = float(a[0] * c * c + a[1] * s * s - a[2] * c * s);
  b[1] = float(a[0] * s * s + a[1] * c * c + a[2] * c * s);
  b[2] = float(2 * c * s * (a[0] - a[1]) + (c * c - s * s) * a[2]);
  b[3] = float(c * a[3] - s * a[4]);
  b[4] = float(s * a[3] + c * a[4]);
  b[5] = a[5];
}

Ptm ApplyMapToPtm(const SynthMap& map, const Ptm& sample) {
  Ptm out;
  out.format = sample.format;
  out.coefficients = Image(map.width, map.height, sample.coefficients.channels());
  if (sample.format == PtmFormat::kLrgb) out.rgb = ApplyMapToImage(map, sample.rgb);
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      const Eigen::Vector2i s = map.SourceTexel(x, y);
      const float rotation = map.rotation_deg[map.index(x, y)];
      const float* a = sample.coefficients.pixel(s.x(), s.y());
      float* b = out.coefficients.pixel(x, y);
      for (int p = 0; p < sample.polynomials(); ++p) {
        if (rotation == 0) std::copy_n(a + 6 * p, 6, b + 6 * p);
        else RotatePtmCoefficients(a + 6 * p, rotation, b + 6 * p);
      }
    }
  return out;
}

}  // namespace mesocap

#include "synth/synth_map.h"

#include <algorithm>
#include <cmath>

#include "core/directions.h"
#include "core/image_io.h"
#include "core/splitmix.h"
#include "core/text_format.h"

namespace mesocap {

SynthMap::SynthMap(int w, int h, int sw, int sh, std::string m)
    : width(w), height(h), sample_width(sw), sample_height(sh), method(std::move(m)),
      source_x(size_t(w) * h, 0.f), source_y(size_t(w) * h, 0.f), rotation_deg(size_t(w) * h, 0.f),
      patch(size_t(w) * h, -1) {}

Eigen::Vector2i SynthMap::SourceTexel(int x, int y) const {
  const size_t i = index(x, y);
  return {std::clamp(int(std::floor(source_x[i])), 0, sample_width - 1),
          std::clamp(int(std::floor(source_y[i])), 0, sample_height - 1)};
}

void SynthMap::Set(int x, int y, float sx, float sy, float rotation, int32_t patch_id) {
  const size_t i = index(x, y);
  source_x[i] = sx;
  source_y[i] = sy;
  rotation_deg[i] = rotation;
  patch[i] = patch_id;
}

int SynthMap::FilledCount() const {
  return int(std::count_if(patch.begin(), patch.end(), [](int32_t p) { return p >= 0; }));
}

Eigen::Vector2d RotatedStep(double du, double dv, double rotation_deg) {
  // Material offset (du, -dv) turned by -rotation, back to (column, row): R(+rotation) in image axes.
  const double c = std::cos(DegToRad(rotation_deg)), s = std::sin(DegToRad(rotation_deg));
  return {c * du - s * dv, s * du + c * dv};
}

Status ValidateMap(const SynthMap& map, bool all_filled) {
  if (map.width <= 0 || map.height <= 0 || map.sample_width <= 0 || map.sample_height <= 0)
    return Status::Error("map has no texels or no sample size");
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      const size_t i = map.index(x, y);
      if (map.patch[i] < 0 && !all_filled) continue;
      if (map.patch[i] < 0) return Status::Error(Format("texel (%d, %d) is not filled", x, y));
      const float sx = map.source_x[i], sy = map.source_y[i];
      if (!(sx >= 0 && sx < map.sample_width && sy >= 0 && sy < map.sample_height) || !std::isfinite(map.rotation_deg[i]))
        return Status::Error(Format("texel (%d, %d) points outside the sample: (%g, %g)", x, y, sx, sy));
    }
  return Status::Ok();
}

Image ApplyMapToImage(const SynthMap& map, const Image& sample) {
  MESOCAP_CHECK(sample.width() == map.sample_width && sample.height() == map.sample_height,
                "the image is not the size of the map's sample");
  Image out(map.width, map.height, sample.channels());
  const int channels = sample.channels();
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      if (!map.filled(x, y)) continue;
      const Eigen::Vector2i s = map.SourceTexel(x, y);
      std::copy_n(sample.pixel(s.x(), s.y()), channels, out.pixel(x, y));
    }
  return out;
}

namespace {
constexpr const char* kChannels[4] = {"source_x", "source_y", "rotation_deg", "patch_id"};
}

Status WriteSynthMap(const std::filesystem::path& path, const SynthMap& map) {
  Image planes(map.width, map.height, 4);
  for (size_t i = 0; i < map.patch.size(); ++i) {
    float* p = planes.data() + 4 * i;
    p[0] = map.source_x[i];
    p[1] = map.source_y[i];
    p[2] = map.rotation_deg[i];
    p[3] = float(map.patch[i]);
  }
  ImageWriteOptions options;
  options.format = PixelFormat::kFloat;
  options.channel_names.assign(std::begin(kChannels), std::end(kChannels));
  options.attributes["mesocap:sample_width"] = map.sample_width;
  options.attributes["mesocap:sample_height"] = map.sample_height;
  options.attributes["mesocap:method"] = map.method;
  options.attributes["mesocap:quantity"] = std::string("texture-coordinate map into the sample");
  return WriteImage(path, planes, options);
}

StatusOr<SynthMap> ReadSynthMap(const std::filesystem::path& path, bool all_filled) {
  ImageReadOptions read;
  read.linearize = false;
  read.max_channels = 64;
  ImageInfo info;
  auto planes = ReadImage(path, read, &info);
  if (!planes.ok()) return planes.status();
  int column[4];
  for (int k = 0; k < 4; ++k) {
    auto it = std::find(info.channel_names.begin(), info.channel_names.end(), kChannels[k]);
    if (it == info.channel_names.end())
      return Status::Error(path.string() + ": not a synthesis map (no channel " + kChannels[k] + ")");
    column[k] = int(it - info.channel_names.begin());
  }
  auto int_attribute = [&](const char* name) {
    auto it = info.attributes.find(name);
    if (it == info.attributes.end()) return 0;
    if (auto* v = std::get_if<int>(&it->second)) return *v;
    // A float attribute of a crafted file may be NaN or beyond int: cast only what an int holds
    // (0 is refused below as a sample size).
    if (auto* v = std::get_if<float>(&it->second)) return std::isfinite(*v) && std::abs(*v) < 1e9f ? int(*v) : 0;
    return 0;
  };
  SynthMap map(planes->width(), planes->height(), int_attribute("mesocap:sample_width"),
               int_attribute("mesocap:sample_height"), "");
  if (auto it = info.attributes.find("mesocap:method"); it != info.attributes.end())
    if (auto* s = std::get_if<std::string>(&it->second)) map.method = *s;
  const int channels = planes->channels();
  for (size_t i = 0; i < map.patch.size(); ++i) {
    const float* p = planes->data() + channels * i;
    map.source_x[i] = p[column[0]];
    map.source_y[i] = p[column[1]];
    map.rotation_deg[i] = p[column[2]];
    const float id = p[column[3]];  // cast only what an int32 holds (a crafted file may hold anything)
    map.patch[i] = std::isfinite(id) && id >= -1.f && id < 2147483520.f ? int32_t(id) : -1;
  }
  if (Status st = ValidateMap(map, all_filled); !st.ok()) return Status::Error(path.string() + ": " + st.message());
  return map;
}

Image PatchPicture(const SynthMap& map) {
  Image out(map.width, map.height, 3);
  auto colour = [](int32_t id, int c) {  // a hash of (id, channel): maps of many patches draw fast
    return 0.15f + 0.7f * float(SplitMix64(uint64_t(uint32_t(id)) << 2 | uint64_t(c)) >> 40) / float(1 << 24);
  };
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      const int32_t id = map.patch[map.index(x, y)];
      const bool cut = (x + 1 < map.width && map.patch[map.index(x + 1, y)] != id) ||
                       (y + 1 < map.height && map.patch[map.index(x, y + 1)] != id);
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = cut || id < 0 ? 0.f : colour(id, c);
    }
  return out;
}

}  // namespace mesocap

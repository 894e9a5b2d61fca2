// The one output of every synthesis method (Tong 2002 §3, Zhou 2005 §III-C): a texture-coordinate
// map, output texel -> (source x, source y, rotation, patch id). Applying the map to every slice
// of the sample gives the synthesized BTF, so mesostructure is identical under all lights and views
// by construction; the map is tiny next to the BTF it indexes.
//
// Coordinates are in sample texels with texel centres at integer + 0.5 (Image::SampleBilinear's
// convention); a lookup takes the texel that contains the point (nearest texel), so applying a map
// copies sample values and never blends them. `rotation_deg` is the angle by which the sample was
// turned, counter-clockwise in the material frame (x right, y up the slice), before it was pasted:
// the output texel shows the sample at directions turned by -rotation (phi - rotation).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/image.h"
#include "core/status.h"

namespace mesocap {

struct SynthMap {
  int width = 0, height = 0;                // output texels
  int sample_width = 0, sample_height = 0;  // texels of the sample the map points into
  std::string method;                       // "roller", "quilt", "paint", ...
  std::vector<float> source_x, source_y;    // per output texel, sample texel coordinates
  std::vector<float> rotation_deg;          // per output texel
  std::vector<int32_t> patch;               // per output texel; -1 = not yet filled

  SynthMap() = default;
  SynthMap(int width, int height, int sample_width, int sample_height, std::string method);

  size_t index(int x, int y) const { return size_t(y) * width + x; }
  bool filled(int x, int y) const { return patch[index(x, y)] >= 0; }
  // The sample texel an output texel copies (clamped into the sample).
  Eigen::Vector2i SourceTexel(int x, int y) const;
  void Set(int x, int y, float sx, float sy, float rotation, int32_t patch_id);
  int FilledCount() const;
};

// Offset in sample texels (columns right, rows down) reached by stepping `du`, `dv` output texels
// inside a patch turned by `rotation_deg` (see above: counter-clockwise in the material frame,
// whose y runs up the slice, i.e. against the rows).
Eigen::Vector2d RotatedStep(double du, double dv, double rotation_deg);

// True when every filled texel's source lies inside the sample and every texel is filled (or,
// with all_filled false, as an atlas map leaves the texels beyond its charts' gutters, not all).
Status ValidateMap(const SynthMap& map, bool all_filled = true);

// Applies the map to one image of the sample (a slice, a colour image, PTM coefficient planes):
// out(x, y) = sample(SourceTexel(x, y)), all channels. Unfilled texels stay zero.
Image ApplyMapToImage(const SynthMap& map, const Image& sample);

// Float OpenEXR with channels source_x, source_y, rotation_deg, patch_id and attributes
// mesocap:sample_width, mesocap:sample_height, mesocap:method (docs/formats.md).
Status WriteSynthMap(const std::filesystem::path& path, const SynthMap& map);
StatusOr<SynthMap> ReadSynthMap(const std::filesystem::path& path, bool all_filled = true);

// Pictures for judging seams: each patch a random flat colour with cut edges drawn black.
Image PatchPicture(const SynthMap& map);

}  // namespace mesocap

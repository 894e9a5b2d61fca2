// The interactive viewer of report.html: a PTM and a BTF relit in WebGL as the mouse moves the
// light, from data inlined in the page (PNG data URIs: the page works offline and from file://,
// where WebGL may not read images beside it). The PTM is drawn from its six coefficient planes;
// the BTF from a tile atlas of its slices at the nearest measured view, blending the three lights
// nearest to the mouse's. A self-test (page URL ending in #selftest) moves the light, reads the
// canvases back and writes the result into <body data-selftest>, with the count of script errors
// in <body data-errors>, for a headless browser to check.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/image.h"
#include "core/status.h"
#include "reconstruct/ptm.h"

namespace mesocap {

struct ViewerSlice {
  Eigen::Vector3d light, view;  // unit, patch frame
  Image image;                  // linear RGB
};

// The viewer's HTML (a <section> with its script). `ptm` may be null and `slices` empty (that
// part is left out). Slices are shown at `tile` texels; `scratch` is a folder for encoding PNGs.
StatusOr<std::string> ViewerHtml(const Ptm* ptm, const std::vector<ViewerSlice>& slices, int tile,
                                 const std::filesystem::path& scratch);

}  // namespace mesocap

// A folder of the virtual rig's true BTF slices in the reconstructed-BTF format (docs/formats.md:
// slices/*.exr and index.json of format "mesocap-btf"), so any stage that reads a BTF folder can be
// fed, and scored against, the truth.
#pragma once

#include <filesystem>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "capture/rig_material.h"
#include "core/status.h"

namespace mesocap {

struct TrueBtfFolderOptions {
  int size = 128;              // texels a side
  double patch_m = 0.064;      // physical side of the patch
  int samples_per_axis = 2;    // texel footprint averaging (see TrueBtfRequest)
  int num_threads = -1;
};

// Renders one slice per (light, view) pair (unit directions, patch frame) into `out` (created;
// must not exist or be empty), written as a staging folder published when complete.
Status WriteTrueBtfFolder(const Material& material, const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& pairs,
                          const TrueBtfFolderOptions& options, const std::filesystem::path& out);

}  // namespace mesocap

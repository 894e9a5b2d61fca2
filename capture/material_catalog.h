// The virtual rig's materials by name, on their own (capture/rig_material.h builds them): the
// front executable lists them in `simulate --help` without linking the renderer.
#pragma once

#include <string>
#include <vector>

namespace mesocap {

struct MaterialInfo {
  std::string name;
  std::string description;
};

// The materials `--material` accepts.
const std::vector<MaterialInfo>& MaterialCatalog();

}  // namespace mesocap

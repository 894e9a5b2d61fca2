#include "capture/material_catalog.h"

namespace mesocap {

const std::vector<MaterialInfo>& MaterialCatalog() {
  static const std::vector<MaterialInfo> catalog = {
      {"weave", "plain weave of blue warp and cream weft, anisotropic fibre twist"},
      {"stones", "rounded stones of varied size and colour in dark mortar"},
      {"corduroy", "rust corduroy: rounded wales along y with fuzzy pile"},
      {"flat", "flat grey Lambertian (albedo 0.5, no specular): for energy checks"},
      {"ggx", "flat, the glTF metallic-roughness BRDF with base colour (0.62, 0.36, 0.18), roughness 0.45, "
              "metallic 0.3: for GGX fits"},
  };
  return catalog;
}

}  // namespace mesocap

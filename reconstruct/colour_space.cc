#include "reconstruct/colour_space.h"

namespace mesocap {

std::string ColourSpaceName(ColourSpace space) {
  switch (space) {
    case ColourSpace::kRgb: return "rgb";
    case ColourSpace::kPrincipalAxes: return "pca";
    case ColourSpace::kChromaticity: return "chromaticity";
  }
  return "unknown";
}

std::optional<ColourSpace> ParseColourSpace(const std::string& name) {
  for (ColourSpace s : kColourSpaces)
    if (ColourSpaceName(s) == name) return s;
  return std::nullopt;
}

}  // namespace mesocap

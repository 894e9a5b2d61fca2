// The colour spaces histograms can be matched in, by name, on their own (reconstruct/colour.h
// converts between them): the front executable lists them in --help without linking the rest.
#pragma once

#include <optional>
#include <string>

namespace mesocap {

// The colour channels a slice's histograms are matched in (3-channel slices; others pass as they
// are):
// - kRgb: R, G and B, each on its own (Ngan & Durand, as Heeger & Bergen's grey method);
// - kPrincipalAxes: the top view's principal colour axes (Heeger & Bergen's colour extension);
// - kChromaticity: brightness R + G + B and the chromaticities r = R / (R + G + B), g = G / (...):
//   a highlight's white then lies inside the colour histograms instead of in a tail that matching
//   hands to dark texels as vivid colour.
enum class ColourSpace { kRgb, kPrincipalAxes, kChromaticity };
inline constexpr ColourSpace kColourSpaces[] = {ColourSpace::kRgb, ColourSpace::kPrincipalAxes, ColourSpace::kChromaticity};
std::string ColourSpaceName(ColourSpace space);  // "rgb", "pca", "chromaticity"
std::optional<ColourSpace> ParseColourSpace(const std::string& name);

}  // namespace mesocap

// The header attributes every BTF slice file carries (docs/formats.md), written by every stage that
// writes slices: measured (calibrate), reconstructed, synthesized, rendered true BTFs and the
// multi-part EXR export.
#pragma once

#include <string>

#include "core/image_io.h"

namespace mesocap {

// What a BTF slice's values are (`mesocap:quantity`).
inline const std::string kBtfSliceQuantity = "BTF: radiance per unit perpendicular irradiance (includes cos theta_i)";

// The slice's light and view angles, in degrees: `mesocap:theta_i_deg`, `phi_i_deg`, `theta_o_deg`,
// `phi_o_deg` (stored as float).
inline void SetSliceAngles(ImageAttributes* attributes, double theta_i_deg, double phi_i_deg, double theta_o_deg,
                           double phi_o_deg) {
  (*attributes)["mesocap:theta_i_deg"] = float(theta_i_deg);
  (*attributes)["mesocap:phi_i_deg"] = float(phi_i_deg);
  (*attributes)["mesocap:theta_o_deg"] = float(theta_o_deg);
  (*attributes)["mesocap:phi_o_deg"] = float(phi_o_deg);
}

}  // namespace mesocap

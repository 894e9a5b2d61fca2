// Pictures of a fitted material (export/ggx_fit.h) on shapes, rendered on the CPU with the glTF
// BRDF under a directional light, orthographic view along -z, no shadows: how it looks in a
// glTF viewer, for the report. Linear RGB out.
#pragma once

#include <Eigen/Core>

#include "core/image.h"
#include "export/ggx_fit.h"

namespace mesocap {

// A sphere filling a `size` x `size` image, the material wrapped `repeats` times around it.
Image RenderMaterialSphere(const GgxMaterialMaps& maps, const Eigen::Vector3d& light, int size, double repeats = 2);

// A cloth-like draped sheet (a height field of soft folds, seen from above at 35 deg), the
// material `repeats` times across it.
Image RenderMaterialCloth(const GgxMaterialMaps& maps, const Eigen::Vector3d& light, int size, double repeats = 3);

}  // namespace mesocap

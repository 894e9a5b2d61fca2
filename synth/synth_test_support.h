// Shared by the synthesis tests: virtual-rig BTF exemplars rendered once per test binary.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "synth/exemplar.h"

namespace mesocap::testing {

// True BTF slices of `material` at `size` texels for a few (light, view) pairs (several lights,
// two views), written once under the temp dir and loaded as an exemplar.
Exemplar VirtualRigExemplar(const std::string& material, int size = 128);
// The same pairs, for tests that render the truth themselves.
std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> ExemplarPairs();

}  // namespace mesocap::testing

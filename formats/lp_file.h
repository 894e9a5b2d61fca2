// RTI light-position files (.lp), the form RTI captures come in: the first line is the number of
// images, then one line per image, `filename x y z`, the light direction in the surface frame
// (x toward the image's right, y toward its top, z toward the camera; see reconstruct/ptm.h).
// Filenames are relative to the .lp file's folder (absolute and Windows paths are accepted; a
// path that does not exist is looked for by its base name beside the .lp file, as RTIBuilder
// folders are often moved after capture).
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <vector>

#include "core/status.h"

namespace mesocap {

struct LpEntry {
  std::filesystem::path image;  // when read: the resolved path of an existing file
  Eigen::Vector3d light_dir = Eigen::Vector3d::UnitZ();
};

// Parses `path`. With require_images_exist, every listed image must exist; the error names the
// .lp file, the line and the missing image. Filenames may contain spaces.
StatusOr<std::vector<LpEntry>> ReadLpFile(const std::filesystem::path& path,
                                          bool require_images_exist = true);

// Writes atomically. Images inside the .lp file's folder are written relative to it.
Status WriteLpFile(const std::filesystem::path& path, const std::vector<LpEntry>& entries);

}  // namespace mesocap

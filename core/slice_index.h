// Reading a slice index (index.json): the list of BTF slices a folder holds, written by
// `calibrate` (format mesocap-slices: a session's measured slices, one board each), by
// `reconstruct` and the virtual rig (format mesocap-btf). Layout: docs/formats.md. Every entry is
// validated here, once, for every reader: a relative file inside the folder, angles in range.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/status.h"

namespace mesocap {

struct SliceIndexEntry {
  std::filesystem::path file;  // the folder of index.json joined with the entry's relative path
  int board = 0;               // 0 when the index has no boards
  double theta_i_deg = 0, phi_i_deg = 0, theta_o_deg = 0, phi_o_deg = 0;  // theta in [0, 90], phi in [0, 360)
  Eigen::Vector3d light = Eigen::Vector3d::UnitZ(), view = Eigen::Vector3d::UnitZ();
  double light_distance_m = 0;  // flash to patch centre (measured slices); 0 when the index has none
  double texel_px = 0;          // a texel's size in the photo, pixels (measured slices); 0 when unknown
};

// A (board, shot) the resampling left out, and why (mesocap-slices).
struct SkippedSlice {
  int board = 0;
  std::string shot;  // the shot's file, relative to the session
  std::string reason;
};

struct SliceIndex {
  std::string format;  // "mesocap-slices", "mesocap-btf", or "" for a bare list
  std::vector<SliceIndexEntry> slices;
  std::vector<SkippedSlice> skipped;  // mesocap-slices; empty when the index lists none
  // mesocap-slices: the shots were JPEGs keeping colour at half resolution ("chroma_subsampled_shots";
  // false when the index does not say).
  bool chroma_subsampled_shots = false;
};

// Reads and validates `index_json`: an object with a "slices" list (or a bare list). Errors name the
// file, the entry and the field.
StatusOr<SliceIndex> ReadSliceIndex(const std::filesystem::path& index_json);

}  // namespace mesocap

// A reconstructed BTF as a folder (format mesocap-btf, docs/formats.md): one half-float OpenEXR
// slice per direction pair with its directions as attributes, and index.json. Written by
// `mesocap reconstruct` and by `mesocap process`'s reconstruct stage.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/json.h"
#include "core/progress.h"
#include "core/status.h"
#include "reconstruct/slice_set.h"

namespace mesocap::app {

using DirectionPair = std::array<double, 4>;  // theta_i, phi_i, theta_o, phi_o in degrees

// The directions of a hemisphere grid (unit, patch frame), empty for an unknown name; GridPairs
// takes every light with every view of them.
std::vector<Eigen::Vector3d> GridDirections(const std::string& grid);

// Every light with every view of a hemisphere grid: "bonn" (81 directions, 6561 pairs, the
// Bonn database's grid the paper validates on) or "coarse" (its rings at 0, 30 and 60 deg with
// every second azimuth: 17 directions, 289 pairs, a quick look). Empty for an unknown name.
std::vector<DirectionPair> GridPairs(const std::string& grid);

// True when `direction` (unit) is one of the coarse grid's 17 directions (within 0.5 deg): the
// slices the viewer and the synth stage take from a finer BTF.
bool OnCoarseGrid(const Eigen::Vector3d& direction);

// The slice file of a direction pair: angles to 0.1 deg, so distinct pairs may share a name.
std::string BtfSliceName(const DirectionPair& pair);

struct BtfFolderReport {
  int slices = 0;
  double seconds = 0;
  double ms_per_slice = 0;
};

// Reconstructs every pair on all cores into `folder` (existing, empty: a staging folder) and
// writes its index.json with `provenance_options`. Cancelled through `progress`: an error.
// The three steps below in one.
StatusOr<BtfFolderReport> WriteReconstructedBtf(const StatisticalBtf& btf, const SliceSetReport& loaded,
                                                const std::vector<DirectionPair>& pairs, bool pixel_only,
                                                int num_threads, const std::filesystem::path& folder,
                                                const Json& provenance_options, const ProgressFn& progress);

// The slices of `pairs` in `folder`'s slices/, and their index entries in order (a shard of a
// sharded reconstruction writes its share so).
struct ReconstructedPairs {
  std::vector<Json> entries;
  double seconds = 0;
};
StatusOr<ReconstructedPairs> ReconstructPairs(const StatisticalBtf& btf, const std::vector<DirectionPair>& pairs,
                                              bool pixel_only, int num_threads, const std::filesystem::path& folder,
                                              const ProgressFn& progress);
// index.json's fields that describe the BTF rather than its slices.
Json BtfIndexHeader(const StatisticalBtf& btf, const SliceSetReport& loaded);
// index.json: `header`, the slices' entries and timing, and the provenance.
StatusOr<BtfFolderReport> WriteBtfIndex(const std::filesystem::path& folder, Json header, const ReconstructedPairs& pairs,
                                        const Json& provenance_options);

}  // namespace mesocap::app

// The benchmarks' exemplar: the virtual rig's weave, head-on, under the 81 Bonn lights, 128 x 128,
// rendered once into `work`.
#pragma once

#include <cstdio>
#include <filesystem>

#include "capture/true_btf_folder.h"
#include "core/directions.h"
#include "reconstruct/statistical_btf.h"

namespace mesocap::bench {

// The folder of the 81 slices (rendered on first use); empty on failure (the reason printed).
inline std::filesystem::path Weave81(const std::filesystem::path& work) {
  const auto folder = work / "weave_81";
  if (std::filesystem::exists(folder / "index.json")) return folder;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> pairs;
  for (const auto& light : BonnDirections()) pairs.push_back({light, Eigen::Vector3d::UnitZ()});
  TrueBtfFolderOptions o;
  o.size = 128;
  o.samples_per_axis = 1;
  if (Status st = WriteTrueBtfFolder(*Material::Create("weave"), pairs, o, folder); !st.ok()) {
    std::fprintf(stderr, "%s\n", st.message().c_str());
    return {};
  }
  return folder;
}

}  // namespace mesocap::bench

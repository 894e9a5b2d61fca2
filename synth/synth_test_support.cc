#include "synth/synth_test_support.h"

#include <map>
#include <mutex>

#include "capture/true_btf_folder.h"
#include "core/directions.h"
#include "core/status.h"

namespace mesocap::testing {

std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> ExemplarPairs() {
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> pairs;
  for (auto [ti, pi] : {std::pair{0.0, 0.0}, {40.0, 0.0}, {40.0, 90.0}, {60.0, 210.0}})
    for (auto [to, po] : {std::pair{0.0, 0.0}, {45.0, 90.0}})
      pairs.push_back({DirectionFromAnglesDeg(ti, pi), DirectionFromAnglesDeg(to, po)});
  return pairs;
}

Exemplar VirtualRigExemplar(const std::string& material, int size) {
  static std::mutex mutex;
  std::lock_guard<std::mutex> lock(mutex);
  const auto dir = std::filesystem::temp_directory_path() /
                   ("mesocap_synth_exemplar_" + std::to_string(getpid()) + "_" + material + "_" + std::to_string(size));
  if (!std::filesystem::exists(dir / "index.json")) {
    auto m = Material::Create(material);
    MESOCAP_CHECK(m.ok(), m.status().message());
    TrueBtfFolderOptions options;
    options.size = size;
    MESOCAP_CHECK(WriteTrueBtfFolder(*m, ExemplarPairs(), options, dir).ok(), "cannot write the exemplar");
  }
  auto e = LoadExemplar(dir);
  MESOCAP_CHECK(e.ok(), e.status().message());
  return std::move(*e);
}

}  // namespace mesocap::testing

#include "core/stage_versions.h"

#include <cstdlib>
#include <map>
#include <sstream>

namespace mesocap {
namespace {

// Bump a stage's number when its outputs change for the same inputs (and say why in the commit).
const std::map<std::string, int>& BuiltInVersions() {
  static const std::map<std::string, int> versions = {
      {"calibrate", 1}, {"resample", 1}, {"fit-ptm", 1}, {"reconstruct", 1}, {"synth", 1}, {"export", 1}, {"decorate", 1}};
  return versions;
}

std::map<std::string, int> Versions() {
  std::map<std::string, int> versions = BuiltInVersions();
  if (const char* text = std::getenv("MESOCAP_STAGE_VERSIONS")) {
    std::stringstream list(text);
    for (std::string item; std::getline(list, item, ',');) {
      const size_t eq = item.find('=');
      if (eq == std::string::npos) continue;
      const auto it = versions.find(item.substr(0, eq));
      if (it != versions.end()) it->second = std::atoi(item.c_str() + eq + 1);
    }
  }
  return versions;
}

}  // namespace

int StageVersion(const std::string& stage) {
  const auto versions = Versions();
  const auto it = versions.find(stage);
  return it == versions.end() ? 0 : it->second;
}

Json StageVersions() {
  Json j = Json::object();
  for (const auto& [stage, version] : Versions()) j[stage] = version;
  return j;
}

}  // namespace mesocap

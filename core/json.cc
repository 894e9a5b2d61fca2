#include "core/json.h"

#include "core/atomic_file.h"

namespace mesocap {

Json ToJson(const Eigen::Matrix3d& m) {
  Json rows = Json::array();
  for (int r = 0; r < 3; ++r) rows.push_back({m(r, 0), m(r, 1), m(r, 2)});
  return rows;
}
Json ToJson(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
Json ToJson(const Eigen::Vector2d& v) { return {v.x(), v.y()}; }

Eigen::Matrix3d Matrix3dFromJson(const Json& j) {
  MESOCAP_CHECK(j.is_array() && j.size() == 3, "expected a 3x3 matrix");
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m(r, c) = j.at(r).at(c).get<double>();
  return m;
}
Eigen::Vector3d Vector3dFromJson(const Json& j) {
  MESOCAP_CHECK(j.is_array() && j.size() == 3, "expected a 3-vector");
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}
Eigen::Vector2d Vector2dFromJson(const Json& j) {
  MESOCAP_CHECK(j.is_array() && j.size() == 2, "expected a 2-vector");
  return {j[0].get<double>(), j[1].get<double>()};
}

StatusOr<Json> ReadJsonFile(const std::filesystem::path& path) {
  auto text = ReadTextFile(path);
  if (!text.ok()) return text.status();
  try {
    return Json::parse(*text);
  } catch (const Json::parse_error& e) {
    return Status::Error(path.string() + ": invalid JSON: " + e.what());
  }
}

Status WriteJsonFile(const std::filesystem::path& path, const Json& json) {
  return WriteTextAtomically(path, json.dump(2) + "\n");
}

}  // namespace mesocap

#include "core/json.h"

#include "core/atomic_file.h"
#include "core/text_format.h"

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

std::string JsonFieldPath(const std::string& path, const std::string& name) {
  return path.empty() ? name : path + "." + name;
}

std::string JsonIndexPath(const std::string& path, size_t index) {
  return path + "[" + std::to_string(index) + "]";
}

const Json& JsonField(const Json& parent, const std::string& path, const std::string& name) {
  if (!parent.is_object())
    throw JsonFieldError((path.empty() ? std::string("the file") : path) + " must be a JSON object, not " +
                         parent.type_name());
  const auto it = parent.find(name);
  if (it == parent.end()) throw JsonFieldError(JsonFieldPath(path, name) + " is missing");
  return *it;
}

double JsonNumber(const Json& j, const std::string& path, double lo, double hi) {
  if (!j.is_number()) throw JsonFieldError(path + " must be a number, not " + std::string(j.type_name()));
  const double v = j.get<double>();
  if (!(v >= lo && v <= hi))
    throw JsonFieldError(Format("%s = %s is outside [%g, %g]", path, j.dump(), lo, hi));
  return v;
}

int JsonInteger(const Json& j, const std::string& path, int lo, int hi) {
  if (!j.is_number_integer())
    throw JsonFieldError(path + " must be an integer, not " + (j.is_number() ? j.dump() : std::string(j.type_name())));
  const auto within = [&](auto v) { return v >= decltype(v)(lo) && v <= decltype(v)(hi); };
  if (j.is_number_unsigned() ? !within(j.get<uint64_t>()) : !within(j.get<int64_t>()))
    throw JsonFieldError(path + " = " + j.dump() + " is outside [" + std::to_string(lo) + ", " +
                         std::to_string(hi) + "]");
  return j.get<int>();
}

std::string JsonString(const Json& j, const std::string& path) {
  if (!j.is_string()) throw JsonFieldError(path + " must be a string, not " + std::string(j.type_name()));
  return j.get<std::string>();
}

const Json& JsonArray(const Json& j, const std::string& path, size_t min_size, size_t max_size) {
  if (!j.is_array()) throw JsonFieldError(path + " must be an array, not " + std::string(j.type_name()));
  if (j.size() < min_size || j.size() > max_size)
    throw JsonFieldError(path + " has " + std::to_string(j.size()) + " entries; " +
                         (min_size == max_size ? "exactly " + std::to_string(min_size)
                                               : "from " + std::to_string(min_size) + " to " + std::to_string(max_size)) +
                         " expected");
  return j;
}

std::filesystem::path JsonRelativePath(const Json& j, const std::string& path) {
  const std::filesystem::path p = JsonString(j, path);
  if (p.empty() || p.has_root_path())
    throw JsonFieldError(path + " = " + j.dump() + " must be a relative path");
  for (const auto& part : p)
    if (part == "..") throw JsonFieldError(path + " = " + j.dump() + " must not leave its folder (\"..\")");
  return p;
}

Eigen::Vector2d JsonVector2d(const Json& j, const std::string& path, double bound) {
  JsonArray(j, path, 2, 2);
  return {JsonNumber(j[0], JsonIndexPath(path, 0), -bound, bound), JsonNumber(j[1], JsonIndexPath(path, 1), -bound, bound)};
}

Eigen::Vector3d JsonVector3d(const Json& j, const std::string& path, double bound) {
  JsonArray(j, path, 3, 3);
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) v[i] = JsonNumber(j[i], JsonIndexPath(path, i), -bound, bound);
  return v;
}

Eigen::Matrix3d JsonMatrix3d(const Json& j, const std::string& path, double bound) {
  JsonArray(j, path, 3, 3);
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r) m.row(r) = JsonVector3d(j[r], JsonIndexPath(path, r), bound).transpose();
  return m;
}

bool JsonBool(const Json& j, const std::string& path) {
  if (!j.is_boolean()) throw JsonFieldError(path + " must be true or false, not " + std::string(j.type_name()));
  return j.get<bool>();
}

StatusOr<Json> ReadJsonFile(const std::filesystem::path& path) {
  auto text = ReadTextFile(path);
  if (!text.ok()) return text.status();
  try {
    return Json::parse(*text);
  } catch (const Json::exception& e) {  // parse errors, and numbers too large for a double (406)
    return Status::Error(path.string() + ": invalid JSON: " + e.what());
  }
}

Status WriteJsonFile(const std::filesystem::path& path, const Json& json) {
  return WriteTextAtomically(path, json.dump(2) + "\n");
}

}  // namespace mesocap

// JSON through nlohmann-json, with Eigen conversions so geometry reads and writes as plain arrays:
// a 3x3 matrix is [[r0],[r1],[r2]], a vector is [x, y, z].
#pragma once

#include <filesystem>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "core/status.h"

namespace mesocap {

using Json = nlohmann::ordered_json;

Json ToJson(const Eigen::Matrix3d& m);
Json ToJson(const Eigen::Vector3d& v);
Json ToJson(const Eigen::Vector2d& v);
Eigen::Matrix3d Matrix3dFromJson(const Json& j);
Eigen::Vector3d Vector3dFromJson(const Json& j);
Eigen::Vector2d Vector2dFromJson(const Json& j);

// Reading manifests written by people: each accessor checks the field's presence, type and range
// and throws JsonFieldError naming its path ("boards[2].size_m") and what was expected. A
// manifest's FromJson catches it once and returns a Status naming the file.
struct JsonFieldError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// The member `name` of object `parent` (whose own path is `path`, "" at the top).
const Json& JsonField(const Json& parent, const std::string& path, const std::string& name);
std::string JsonFieldPath(const std::string& path, const std::string& name);
std::string JsonIndexPath(const std::string& path, size_t index);
double JsonNumber(const Json& j, const std::string& path, double lo, double hi);
int JsonInteger(const Json& j, const std::string& path, int lo, int hi);
std::string JsonString(const Json& j, const std::string& path);
// An array whose size lies in [min_size, max_size].
const Json& JsonArray(const Json& j, const std::string& path, size_t min_size, size_t max_size);
// A relative path inside the folder it is read from: no root, no "..", not empty.
std::filesystem::path JsonRelativePath(const Json& j, const std::string& path);
Eigen::Vector2d JsonVector2d(const Json& j, const std::string& path, double bound);
Eigen::Vector3d JsonVector3d(const Json& j, const std::string& path, double bound);
Eigen::Matrix3d JsonMatrix3d(const Json& j, const std::string& path, double bound);  // rows
bool JsonBool(const Json& j, const std::string& path);

// Parses a JSON file; the error names the file and the parser's position.
StatusOr<Json> ReadJsonFile(const std::filesystem::path& path);
// A record read from the JSON file `path` by `read` (Json -> T, throwing JsonFieldError on a bad
// field): T, or an error naming the file and the field.
template <typename Read>
auto ReadJsonRecord(const std::filesystem::path& path, Read&& read)
    -> StatusOr<std::decay_t<decltype(read(std::declval<const Json&>()))>> {
  auto json = ReadJsonFile(path);
  if (!json.ok()) return json.status();
  try {
    return read(*json);
  } catch (const std::exception& e) {
    return Status::Error(path.string() + ": " + e.what());
  }
}
// Writes pretty JSON atomically (temp + fsync + rename).
Status WriteJsonFile(const std::filesystem::path& path, const Json& json);

}  // namespace mesocap

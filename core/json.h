// JSON through nlohmann-json, with Eigen conversions so geometry reads and writes as plain arrays:
// a 3x3 matrix is [[r0],[r1],[r2]], a vector is [x, y, z].
#pragma once

#include <filesystem>

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

// Parses a JSON file; the error names the file and the parser's position.
StatusOr<Json> ReadJsonFile(const std::filesystem::path& path);
// Writes pretty JSON atomically (temp + fsync + rename).
Status WriteJsonFile(const std::filesystem::path& path, const Json& json);

}  // namespace mesocap

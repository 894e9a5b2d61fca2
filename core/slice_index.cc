#include "core/slice_index.h"

#include <cmath>

#include "core/directions.h"
#include "core/json.h"

namespace mesocap {
namespace {

constexpr size_t kMaxSlices = 1 << 20;

// Azimuth into [0, 360): 400 and -40 are the same direction as 40 and 320.
double NormalisedAzimuth(double phi_deg) {
  const double phi = std::fmod(phi_deg, 360.0);
  return phi < 0 ? phi + 360.0 : (phi >= 360.0 ? 0.0 : phi);
}

SliceIndexEntry EntryFromJson(const Json& e, const std::string& at, const std::filesystem::path& folder) {
  SliceIndexEntry s;
  s.file = folder / JsonRelativePath(JsonField(e, at, "file"), JsonFieldPath(at, "file"));
  if (e.is_object() && e.contains("board")) s.board = JsonInteger(e["board"], JsonFieldPath(at, "board"), 0, 1 << 20);
  const auto theta = [&](const char* name) { return JsonNumber(JsonField(e, at, name), JsonFieldPath(at, name), 0, 90); };
  const auto phi = [&](const char* name) {
    return NormalisedAzimuth(JsonNumber(JsonField(e, at, name), JsonFieldPath(at, name), -720, 720));
  };
  s.theta_i_deg = theta("theta_i_deg");
  s.phi_i_deg = phi("phi_i_deg");
  s.theta_o_deg = theta("theta_o_deg");
  s.phi_o_deg = phi("phi_o_deg");
  s.light = DirectionFromAnglesDeg(s.theta_i_deg, s.phi_i_deg);
  s.view = DirectionFromAnglesDeg(s.theta_o_deg, s.phi_o_deg);
  if (e.is_object() && e.contains("light_distance_m"))
    s.light_distance_m = JsonNumber(e["light_distance_m"], JsonFieldPath(at, "light_distance_m"), 0, 1e3);
  if (e.is_object() && e.contains("texel_px"))
    s.texel_px = JsonNumber(e["texel_px"], JsonFieldPath(at, "texel_px"), 0, 1e4);
  return s;
}

}  // namespace

StatusOr<SliceIndex> ReadSliceIndex(const std::filesystem::path& index_json) {
  auto json = ReadJsonFile(index_json);
  if (!json.ok()) return json.status();
  SliceIndex index;
  try {
    const bool bare = json->is_array();
    if (!bare) index.format = json->is_object() && json->contains("format") ? JsonString((*json)["format"], "format") : "";
    if (!bare && json->is_object() && json->contains("chroma_subsampled_shots"))
      index.chroma_subsampled_shots = JsonBool((*json)["chroma_subsampled_shots"], "chroma_subsampled_shots");
    const std::string list_at = bare ? "the list" : "slices";
    const Json& list = JsonArray(bare ? *json : JsonField(*json, "", "slices"), list_at, 1, kMaxSlices);
    for (size_t k = 0; k < list.size(); ++k)
      index.slices.push_back(EntryFromJson(list[k], JsonIndexPath(bare ? "" : "slices", k), index_json.parent_path()));
    if (!bare && json->contains("skipped")) {
      const Json& skipped = JsonArray((*json)["skipped"], "skipped", 0, kMaxSlices);
      for (size_t k = 0; k < skipped.size(); ++k) {
        const std::string at = JsonIndexPath("skipped", k);
        index.skipped.push_back({JsonInteger(JsonField(skipped[k], at, "board"), JsonFieldPath(at, "board"), 0, 1 << 20),
                                 JsonString(JsonField(skipped[k], at, "shot"), JsonFieldPath(at, "shot")),
                                 JsonString(JsonField(skipped[k], at, "reason"), JsonFieldPath(at, "reason"))});
      }
    }
  } catch (const std::exception& e) {
    return Status::Error(index_json.string() + ": " + e.what());
  }
  return index;
}

}  // namespace mesocap

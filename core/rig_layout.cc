#include "core/rig_layout.h"

namespace mesocap {

namespace {

Json BoardsToJson(const std::vector<LayoutBoard>& boards) {
  Json boards_json = Json::array();
  for (const auto& b : boards) {
    Json tags_json = Json::array();
    for (const auto& t : b.tags) {
      Json corners = Json::array();
      for (const auto& c : t.corners_m) corners.push_back(mesocap::ToJson(c));
      tags_json.push_back({{"id", t.id}, {"size_m", t.size_m}, {"corners_m", corners}});
    }
    boards_json.push_back({{"id", b.id}, {"size_m", b.size_m}, {"patch_m", b.patch_m},
                           {"nominal_incidence_deg", b.nominal_incidence_deg}, {"tags", tags_json}});
  }
  return boards_json;
}

// Limits a real rig stays far inside; beyond them a layout is a typo or a crafted file.
constexpr int kMaxBoards = 64, kMaxTagsPerBoard = 64, kMaxTagId = 586;  // tag36h11 has 587 codes
constexpr double kMaxSizeM = 10;

std::vector<LayoutBoard> BoardsFromJson(const Json& j, const std::string& path, size_t min_count) {
  std::vector<LayoutBoard> boards;
  JsonArray(j, path, min_count, kMaxBoards);
  for (size_t i = 0; i < j.size(); ++i) {
    const std::string at = JsonIndexPath(path, i);
    const Json& jb = j[i];
    LayoutBoard b;
    b.id = JsonInteger(JsonField(jb, at, "id"), JsonFieldPath(at, "id"), 0, 1 << 20);
    b.size_m = JsonNumber(JsonField(jb, at, "size_m"), JsonFieldPath(at, "size_m"), 1e-4, kMaxSizeM);
    b.patch_m = JsonNumber(JsonField(jb, at, "patch_m"), JsonFieldPath(at, "patch_m"), 1e-4, b.size_m);
    if (jb.contains("nominal_incidence_deg"))
      b.nominal_incidence_deg =
          JsonNumber(jb["nominal_incidence_deg"], JsonFieldPath(at, "nominal_incidence_deg"), 0, 89);
    const std::string tags_at = JsonFieldPath(at, "tags");
    const Json& tags = JsonArray(JsonField(jb, at, "tags"), tags_at, 1, kMaxTagsPerBoard);
    for (size_t k = 0; k < tags.size(); ++k) {
      const std::string tag_at = JsonIndexPath(tags_at, k);
      LayoutTag t;
      t.id = JsonInteger(JsonField(tags[k], tag_at, "id"), JsonFieldPath(tag_at, "id"), 0, kMaxTagId);
      t.size_m = JsonNumber(JsonField(tags[k], tag_at, "size_m"), JsonFieldPath(tag_at, "size_m"), 1e-4, b.size_m);
      const std::string corners_at = JsonFieldPath(tag_at, "corners_m");
      const Json& corners = JsonArray(JsonField(tags[k], tag_at, "corners_m"), corners_at, 4, 4);
      for (int c = 0; c < 4; ++c) t.corners_m[c] = JsonVector2d(corners[c], JsonIndexPath(corners_at, c), b.size_m);
      b.tags.push_back(t);
    }
    for (const LayoutBoard& other : boards)
      if (other.id == b.id) throw JsonFieldError(JsonFieldPath(at, "id") + " = " + std::to_string(b.id) + " is used twice");
    boards.push_back(b);
  }
  return boards;
}

}  // namespace

Json RigLayout::ToJson() const {
  return {{"format", "mesocap-rig-layout"}, {"format_version", 1}, {"tag_family", tag_family},
          {"boards", BoardsToJson(boards)},
          {"spheres", {{"count", sphere_count}, {"radius_m", sphere_radius_m}}},
          {"grey_cards", {{"albedo", grey_card_albedo}, {"mounts", BoardsToJson(grey_cards)}}},
          {"checkerboard", {{"cols", checker_cols}, {"rows", checker_rows}, {"square_m", checker_square_m}}}};
}

StatusOr<RigLayout> RigLayout::FromJson(const Json& j) {
  try {
    RigLayout l;
    if (!j.is_object()) throw JsonFieldError(std::string("the layout must be a JSON object, not ") + j.type_name());
    if (j.contains("tag_family")) l.tag_family = JsonString(j["tag_family"], "tag_family");
    if (l.tag_family != "tag36h11")
      throw JsonFieldError("tag_family '" + l.tag_family + "' is not supported (only tag36h11)");
    l.boards = BoardsFromJson(JsonField(j, "", "boards"), "boards", 1);
    const Json& spheres = JsonField(j, "", "spheres");
    l.sphere_count = JsonInteger(JsonField(spheres, "spheres", "count"), "spheres.count", 1, 16);
    l.sphere_radius_m = JsonNumber(JsonField(spheres, "spheres", "radius_m"), "spheres.radius_m", 1e-3, 1);
    const Json& cards = JsonField(j, "", "grey_cards");
    l.grey_cards = BoardsFromJson(JsonField(cards, "grey_cards", "mounts"), "grey_cards.mounts", 1);
    l.grey_card_albedo = JsonNumber(JsonField(cards, "grey_cards", "albedo"), "grey_cards.albedo", 0.01, 1);
    const Json& checker = JsonField(j, "", "checkerboard");
    l.checker_cols = JsonInteger(JsonField(checker, "checkerboard", "cols"), "checkerboard.cols", 2, 200);
    l.checker_rows = JsonInteger(JsonField(checker, "checkerboard", "rows"), "checkerboard.rows", 2, 200);
    l.checker_square_m = JsonNumber(JsonField(checker, "checkerboard", "square_m"), "checkerboard.square_m", 1e-4, 1);
    return l;
  } catch (const std::exception& e) {
    return Status::Error(std::string("rig layout: ") + e.what());
  }
}

}  // namespace mesocap

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

std::vector<LayoutBoard> BoardsFromJson(const Json& j) {
  std::vector<LayoutBoard> boards;
  for (const auto& jb : j) {
    LayoutBoard b;
    b.id = jb.at("id");
    b.size_m = jb.at("size_m");
    b.patch_m = jb.at("patch_m");
    b.nominal_incidence_deg = jb.value("nominal_incidence_deg", 0.0);
    for (const auto& jt : jb.at("tags")) {
      LayoutTag t;
      t.id = jt.at("id");
      t.size_m = jt.at("size_m");
      for (int k = 0; k < 4; ++k) t.corners_m[k] = Vector2dFromJson(jt.at("corners_m").at(k));
      b.tags.push_back(t);
    }
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
    l.tag_family = j.value("tag_family", "tag36h11");
    l.boards = BoardsFromJson(j.at("boards"));
    l.sphere_count = j.at("spheres").at("count");
    l.sphere_radius_m = j.at("spheres").at("radius_m");
    l.grey_cards = BoardsFromJson(j.at("grey_cards").at("mounts"));
    l.grey_card_albedo = j.at("grey_cards").at("albedo");
    l.checker_cols = j.at("checkerboard").at("cols");
    l.checker_rows = j.at("checkerboard").at("rows");
    l.checker_square_m = j.at("checkerboard").at("square_m");
    if (l.boards.empty()) return Status::Error("rig layout has no boards");
    if (l.sphere_radius_m <= 0) return Status::Error("rig layout: spheres.radius_m must be positive");
    return l;
  } catch (const std::exception& e) {
    return Status::Error(std::string("rig layout: ") + e.what());
  }
}

}  // namespace mesocap

#include "calib/marked_corners.h"

#include <algorithm>

#include "core/json.h"

namespace mesocap {

int OutlineTagId(int board_id) { return -1 - board_id; }

std::vector<LayoutBoard> WithOutlineTags(std::vector<LayoutBoard> boards) {
  for (LayoutBoard& b : boards) {
    const double h = b.size_m / 2;
    LayoutTag outline;
    outline.id = OutlineTagId(b.id);
    outline.size_m = b.size_m;
    outline.corners_m = {Eigen::Vector2d(-h, -h), Eigen::Vector2d(h, -h), Eigen::Vector2d(h, h), Eigen::Vector2d(-h, h)};
    b.tags.push_back(outline);
  }
  return boards;
}

StatusOr<std::map<std::string, std::vector<TagDetection>>> ReadMarkedCorners(const std::filesystem::path& path,
                                                                          const std::vector<LayoutBoard>& boards,
                                                                          int image_width, int image_height) {
  auto json = ReadJsonFile(path);
  if (!json.ok()) return json.status();
  std::map<std::string, std::vector<TagDetection>> marked;
  try {
    const Json& shots = JsonArray(JsonField(*json, "", "shots"), "shots", 1, 1 << 20);
    for (size_t s = 0; s < shots.size(); ++s) {
      const std::string at = JsonIndexPath("shots", s);
      const std::string file = JsonRelativePath(JsonField(shots[s], at, "file"), JsonFieldPath(at, "file")).generic_string();
      const std::string boards_at = JsonFieldPath(at, "boards");
      const Json& list = JsonArray(JsonField(shots[s], at, "boards"), boards_at, 1, 64);
      for (size_t b = 0; b < list.size(); ++b) {
        const std::string board_at = JsonIndexPath(boards_at, b);
        const int id = JsonInteger(JsonField(list[b], board_at, "id"), JsonFieldPath(board_at, "id"), 0, 1 << 20);
        if (std::none_of(boards.begin(), boards.end(), [&](const LayoutBoard& l) { return l.id == id; }))
          throw JsonFieldError(JsonFieldPath(board_at, "id") + " = " + std::to_string(id) + " is not a board of the layout");
        const std::string corners_at = JsonFieldPath(board_at, "corners_px");
        const Json& corners = JsonArray(JsonField(list[b], board_at, "corners_px"), corners_at, 4, 4);
        TagDetection d;
        d.id = OutlineTagId(id);
        d.decision_margin = 255;  // placed by a person
        for (int c = 0; c < 4; ++c) {
          const std::string corner_at = JsonIndexPath(corners_at, c);
          JsonArray(corners[c], corner_at, 2, 2);
          d.corners_px[c] = {JsonNumber(corners[c][0], JsonIndexPath(corner_at, 0), -0.5, image_width - 0.5),
                             JsonNumber(corners[c][1], JsonIndexPath(corner_at, 1), -0.5, image_height - 0.5)};
        }
        marked[file].push_back(d);
      }
    }
  } catch (const std::exception& e) {
    return Status::Error(path.string() + ": " + e.what());
  }
  return marked;
}

}  // namespace mesocap

// Hand-marked board corners: the fallback when a board's AprilTags cannot be decoded in any photo
// (glare on a glossy sample, a tag covered or out of focus). A person marks, in one or more
// shots, the pixel positions of the four corners of the board's square backing. Format
// (docs/formats.md), corners in the order of the board frame (-h,-h), (h,-h), (h,h), (-h,h) with
// h = size_m / 2, x along the board's first axis:
//   {"format": "mesocap-marked-corners",
//    "shots": [{"file": "shots/shot_0001.jpg", "boards": [{"id": 3, "corners_px": [[x,y] x 4]}]}]}
// Each marked board becomes a pseudo-tag spanning the whole board, so the poses come from the
// same robust solve as the tags' (board_poses.h), alongside any tags that were decoded.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "calib/tag_detection.h"
#include "core/rig_layout.h"
#include "core/status.h"

namespace mesocap {

// The pseudo-tag id of a board's outline: negative, so never a real tag's.
int OutlineTagId(int board_id);

// Marked outlines per shot file (as in the journal, relative to the session), as detections of
// the boards' outline pseudo-tags. Errors name the file and the field; a board id not in
// `boards` is an error.
StatusOr<std::map<std::string, std::vector<TagDetection>>> ReadMarkedCorners(const std::filesystem::path& path,
                                                                          const std::vector<LayoutBoard>& boards,
                                                                          int image_width, int image_height);

// `boards` with each board's outline added as a pseudo-tag.
std::vector<LayoutBoard> WithOutlineTags(std::vector<LayoutBoard> boards);

}  // namespace mesocap

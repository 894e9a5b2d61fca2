// Real AprilTag bit patterns (tag36h11) from libapriltag, so both libapriltag and OpenCV's
// aruco module detect the rendered tags.
#pragma once

#include <vector>

namespace mesocap {

struct TagBitmap {
  int cells = 0;            // total width in cells, white border included (10 for tag36h11)
  int border_cells = 0;     // width at the black border (8): the tag's "size"
  std::vector<bool> white;  // cells * cells, row-major, row 0 at the top of the upright tag
};

// Bitmap of tag36h11 number `id`. Throws for an id outside the family.
TagBitmap Tag36h11Bitmap(int id);
int Tag36h11Count();

}  // namespace mesocap

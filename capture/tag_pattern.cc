#include "capture/tag_pattern.h"

#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>

#include <cstdlib>
#include <memory>

#include "core/status.h"

namespace mesocap {
namespace {

struct FamilyDeleter {
  void operator()(apriltag_family_t* f) const { tag36h11_destroy(f); }
};

apriltag_family_t* Family() {
  static std::unique_ptr<apriltag_family_t, FamilyDeleter> family(tag36h11_create());
  return family.get();
}

}  // namespace

int Tag36h11Count() { return int(Family()->ncodes); }

TagBitmap Tag36h11Bitmap(int id) {
  MESOCAP_CHECK(id >= 0 && id < Tag36h11Count(), "tag36h11 id out of range");
  image_u8_t* im = apriltag_to_image(Family(), id);
  TagBitmap bitmap;
  bitmap.cells = Family()->total_width;
  bitmap.border_cells = Family()->width_at_border;
  bitmap.white.resize(size_t(bitmap.cells) * bitmap.cells);
  for (int y = 0; y < bitmap.cells; ++y)
    for (int x = 0; x < bitmap.cells; ++x)
      bitmap.white[size_t(y) * bitmap.cells + x] = im->buf[y * im->stride + x] > 127;
  // Debian's libapriltag does not export image_u8_destroy; this is what it does.
  std::free(im->buf);
  std::free(im);
  return bitmap;
}

}  // namespace mesocap

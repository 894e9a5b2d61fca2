// What a photo's metadata says, as the session journal keeps it: shared by `import` (photos
// from a folder) and `capture` (photos from the camera).
#pragma once

#include <optional>
#include <string>

#include "core/image_io.h"
#include "core/json.h"

namespace mesocap {

// A string attribute; null when absent or not a string.
const std::string* StringAttr(const ImageAttributes& attrs, const std::string& name);

// A numeric attribute whatever type OpenImageIO gave it (small EXIF integers arrive as strings);
// empty when absent or not a finite number.
std::optional<double> NumberAttr(const ImageAttributes& attrs, const std::string& name);

// The EXIF fields the session journal keeps, with the names the virtual rig uses, plus the
// file's format, size and bit depth.
Json ExifOf(const ImageInfo& info);

}  // namespace mesocap

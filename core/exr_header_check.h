// OpenEXR allocates from its header while opening a file, before OpenImageIO hands mesocap the
// image size: the attributes' declared byte sizes, the chunk-offset table (one 64-bit offset per
// scanline block or tile, sized from the data window) and, when reading, buffers for every
// declared channel. A few hundred crafted bytes can ask for gigabytes. This reads the headers
// (every part of a multi-part file) first and refuses what the file cannot back.
#pragma once

#include <cstdint>
#include <filesystem>

#include "core/status.h"

namespace mesocap {

// Ok for files that are not OpenEXR. For OpenEXR: an error naming `path` when an attribute
// declares more bytes than the file holds, when the offset table alone would not fit in the file,
// or when CheckImageSize refuses the data window and channels. A header too malformed to walk
// is left to OpenEXR's own reader, which reports it.
Status CheckExrHeader(const std::filesystem::path& path);

}  // namespace mesocap

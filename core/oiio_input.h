// Opening an image with OpenImageIO's reader for its extension only. OpenImageIO's own open()
// falls back to trying every reader it has when the named one fails, so a corrupt .jpg reaches
// readers for formats no photo folder holds (its RLA reader aborts the process on some inputs,
// found by fuzz/fuzz_image_u8). The extension decides; a file that does not match it is an error.
#pragma once

#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <memory>
#include <string>

namespace mesocap {

// The opened reader, or nullptr with *error saying why (without the path).
std::unique_ptr<OIIO::ImageInput> OpenImageForExtension(const std::filesystem::path& path, const OIIO::ImageSpec* config,
                                                        std::string* error);

}  // namespace mesocap

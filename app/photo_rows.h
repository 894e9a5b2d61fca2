// The photos fit-ptm streams, each read in the order of its rows. A sequential JPEG is read from
// its open decoder. A progressive JPEG's decoder would hold the whole image's coefficients for as
// long as it is open (about 3 bytes a pixel at 4:4:4, every photo at once), so those are decoded
// whole, a few at a time, when opened, and their bytes parked in a scratch file (page cache, not
// our memory) to be read back a band at a time.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

#include "core/image_u8_io.h"
#include "core/scratch_file.h"
#include "core/status.h"
#include "formats/lp_file.h"

namespace mesocap::app {

class PhotoRows {
 public:
  explicit PhotoRows(std::unique_ptr<JpegRowReader> decoder);
  // Rows of `width` * `channels` bytes stored one after another from `offset` in `park`.
  PhotoRows(std::shared_ptr<const ScratchFile> park, uint64_t offset, int width, int height, int channels);

  int width() const { return width_; }
  int height() const { return height_; }
  int channels() const { return channels_; }
  bool parked() const { return park_ != nullptr; }
  // The next `count` rows into rows[0..count).
  Status ReadRows(int count, uint8_t* const* rows);

 private:
  std::unique_ptr<JpegRowReader> decoder_;
  std::shared_ptr<const ScratchFile> park_;
  uint64_t offset_ = 0;
  int width_ = 0, height_ = 0, channels_ = 0, next_row_ = 0;
};

// Every photo as rows when all are 8-bit JPEGs; empty when one is not (read them whole). The
// progressive ones are decoded here, `threads` at a time, into a scratch file in `scratch_folder`.
// An unreadable or corrupt JPEG is an error naming it.
StatusOr<std::vector<PhotoRows>> OpenPhotoRows(const std::vector<LpEntry>& entries,
                                               const std::filesystem::path& scratch_folder, int threads);

}  // namespace mesocap::app

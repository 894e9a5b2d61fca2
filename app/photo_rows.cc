#include "app/photo_rows.h"

#include <atomic>
#include <optional>
#include <string>

#include "core/cancel.h"
#include "core/parallel.h"

namespace mesocap::app {
namespace fs = std::filesystem;

PhotoRows::PhotoRows(std::unique_ptr<JpegRowReader> decoder)
    : decoder_(std::move(decoder)),
      width_(decoder_->width()),
      height_(decoder_->height()),
      channels_(decoder_->channels()) {}

PhotoRows::PhotoRows(std::shared_ptr<const ScratchFile> park, uint64_t offset, int width, int height, int channels)
    : park_(std::move(park)), offset_(offset), width_(width), height_(height), channels_(channels) {}

Status PhotoRows::ReadRows(int count, uint8_t* const* rows) {
  if (decoder_) return decoder_->ReadRows(count, rows);
  const size_t row_bytes = size_t(width_) * size_t(channels_);
  for (int r = 0; r < count; ++r)
    MESOCAP_RETURN_IF_ERROR(park_->Read(offset_ + uint64_t(next_row_ + r) * row_bytes, rows[r], row_bytes));
  next_row_ += count;
  return Status::Ok();
}

namespace {

// A progressive JPEG decoded whole and written at the next free offset of `park`.
StatusOr<PhotoRows> ParkWhole(JpegRowReader& decoder, const std::shared_ptr<const ScratchFile>& park,
                              std::atomic<uint64_t>* next_offset) {
  auto image = decoder.ReadAll();
  if (!image.ok()) return image.status();
  const uint64_t bytes = uint64_t(image->width()) * uint64_t(image->height()) * uint64_t(image->channels());
  const uint64_t offset = next_offset->fetch_add(bytes);
  MESOCAP_RETURN_IF_ERROR(park->Write(offset, image->data(), size_t(bytes)));
  return PhotoRows(park, offset, image->width(), image->height(), image->channels());
}

}  // namespace

StatusOr<std::vector<PhotoRows>> OpenPhotoRows(const std::vector<LpEntry>& entries, const fs::path& scratch_folder,
                                               int threads) {
  const int n = int(entries.size());
  auto created = ScratchFile::Create(scratch_folder);
  if (!created.ok()) return created.status();
  const auto park = std::make_shared<const ScratchFile>(std::move(*created));
  std::atomic<uint64_t> next_offset{0};
  std::vector<std::optional<PhotoRows>> photos(entries.size());
  std::vector<std::string> errors(entries.size());
  std::atomic<bool> all_jpeg{true};
  ParallelFor(
      0, n,
      [&](int i) {
        if (!all_jpeg || CancelRequested()) return;
        const fs::path& file = entries[size_t(i)].image;
        auto sequential = JpegRowReader::Open(file, 3, 0, JpegRowReader::Scans::kSequentialOnly);
        if (!sequential.ok()) {
          errors[size_t(i)] = sequential.status().message();
        } else if (*sequential) {
          photos[size_t(i)].emplace(std::move(*sequential));
        } else if (auto any = JpegRowReader::Open(file, 3); !any.ok()) {
          errors[size_t(i)] = any.status().message();
        } else if (!*any) {
          all_jpeg = false;  // not an 8-bit JPEG
        } else if (auto parked = ParkWhole(**any, park, &next_offset); !parked.ok()) {
          errors[size_t(i)] = parked.status().message();
        } else {
          photos[size_t(i)].emplace(std::move(*parked));
        }
      },
      threads);
  if (CancelRequested()) return Status::Cancelled();
  for (const std::string& error : errors)
    if (!error.empty()) return Status::Error(error);
  std::vector<PhotoRows> rows;
  if (!all_jpeg) return rows;
  rows.reserve(entries.size());
  for (auto& photo : photos) rows.push_back(std::move(*photo));
  return rows;
}

}  // namespace mesocap::app

#include "core/binary_record.h"

#include "core/atomic_file.h"

namespace mesocap {

Status BinaryRecordWriter::WriteTo(const std::filesystem::path& file) const { return WriteTextAtomically(file, bytes_); }

StatusOr<BinaryRecordReader> BinaryRecordReader::Open(const std::filesystem::path& file, const std::string& format) {
  auto text = ReadTextFile(file);
  if (!text.ok()) return text.status();
  const size_t eol = text->find('\n');
  if (eol == std::string::npos || text->compare(0, eol, format) != 0)
    return Status::Error(file.string() + ": not a " + format + " record (written by another mesocap version?)");
  BinaryRecordReader reader;
  reader.file_ = file;
  reader.bytes_ = std::move(*text);
  reader.at_ = eol + 1;
  return reader;
}

void BinaryRecordReader::Take(void* p, size_t n) {
  if (!error_.empty()) return;
  if (bytes_.size() - at_ < n) {
    error_ = "ends early at byte " + std::to_string(at_);
    return;
  }
  std::memcpy(p, bytes_.data() + at_, n);
  at_ += n;
}

size_t BinaryRecordReader::Count(uint64_t limit) {
  const uint64_t n = U64();
  if (n <= limit) return size_t(n);
  if (error_.empty()) error_ = "a count of " + std::to_string(n) + " at byte " + std::to_string(at_ - 8) + " exceeds " +
                               std::to_string(limit);
  return 0;
}

std::vector<float> BinaryRecordReader::Floats() {
  std::vector<float> v(Count((bytes_.size() - at_) / sizeof(float)));
  Take(v.data(), v.size() * sizeof(float));
  return v;
}

std::string BinaryRecordReader::Text() {
  std::string v(Count(bytes_.size() - at_), '\0');
  Take(v.data(), v.size());
  return v;
}

Status BinaryRecordReader::Finish() const {
  if (!error_.empty()) return Status::Error(file_.string() + ": corrupt: " + error_);
  if (at_ != bytes_.size())
    return Status::Error(file_.string() + ": corrupt: " + std::to_string(bytes_.size() - at_) + " bytes after the record");
  return Status::Ok();
}

}  // namespace mesocap

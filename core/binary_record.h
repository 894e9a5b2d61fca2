// A small binary record for intermediate results that several jobs share (the statistics the
// shards of a sharded stage read, docs/workflow.md): a magic line naming the format and its
// version, then little-endian fields written in order and read back in the same order. Every read
// is bounds-checked; a short, foreign or newer file is an error naming the file, never a crash.
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "core/status.h"

namespace mesocap {

class BinaryRecordWriter {
 public:
  explicit BinaryRecordWriter(const std::string& format) { Bytes(format.data(), format.size()), U8('\n'); }
  void U8(uint8_t v) { bytes_.push_back(char(v)); }
  void I32(int32_t v) { Bytes(&v, sizeof v); }
  void U64(uint64_t v) { Bytes(&v, sizeof v); }
  void F64(double v) { Bytes(&v, sizeof v); }
  void Floats(std::span<const float> v) { U64(v.size()), Bytes(v.data(), v.size_bytes()); }
  void Text(const std::string& v) { U64(v.size()), Bytes(v.data(), v.size()); }
  const std::string& bytes() const { return bytes_; }
  // Written atomically (core/atomic_file.h).
  Status WriteTo(const std::filesystem::path& file) const;

 private:
  void Bytes(const void* p, size_t n) { bytes_.append(static_cast<const char*>(p), n); }
  std::string bytes_;
};

class BinaryRecordReader {
 public:
  // Reads `file` whole and checks its first line is `format`.
  static StatusOr<BinaryRecordReader> Open(const std::filesystem::path& file, const std::string& format);

  uint8_t U8() { uint8_t v = 0; return Take(&v, sizeof v), v; }
  int32_t I32() { int32_t v = 0; return Take(&v, sizeof v), v; }
  uint64_t U64() { uint64_t v = 0; return Take(&v, sizeof v), v; }
  double F64() { double v = 0; return Take(&v, sizeof v), v; }
  std::vector<float> Floats();
  std::string Text();
  // A count that must lie in [0, limit]; beyond it the record is marked broken (0 returned).
  size_t Count(uint64_t limit);
  // A value read is impossible: the record is broken (Finish says `why`).
  void MarkBroken(const std::string& why) {
    if (error_.empty()) error_ = why + " before byte " + std::to_string(at_);
  }
  // After the reads: an error naming the file if any read ran past its end or met a bad count,
  // or if bytes are left over.
  Status Finish() const;
  bool ok() const { return error_.empty(); }

 private:
  void Take(void* p, size_t n);
  std::filesystem::path file_;
  std::string bytes_;
  size_t at_ = 0;
  std::string error_;
};

}  // namespace mesocap

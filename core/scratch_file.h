// Intermediate data parked in the kernel's page cache instead of our own memory: an unnamed
// temporary file, gone when closed (or when the process dies). For results too large to hold
// in fresh memory cheaply: on the virtual machines we run on, each fresh 4 KiB page costs a
// fault of 6-16 us (fit-ptm's 216 MB of float coefficients: 0.3-0.9 s of faults), while writing
// and reading the same bytes through the page cache costs about 0.05 s. The kernel may also
// write the pages to disk and drop them under memory pressure, so memory stays bounded.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "core/status.h"

namespace mesocap {

class ScratchFile {
 public:
  // In `folder` (O_TMPFILE; on file systems without it, a named file removed at once). The
  // error names the folder.
  static StatusOr<ScratchFile> Create(const std::filesystem::path& folder);
  ScratchFile(ScratchFile&& other) noexcept : fd_(other.fd_), folder_(std::move(other.folder_)) { other.fd_ = -1; }
  ScratchFile& operator=(ScratchFile&& other) noexcept;
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;
  ~ScratchFile();

  // Safe to call from several threads at once on disjoint ranges. Read fails on a range that was
  // never written (a short read).
  Status Write(uint64_t offset, const void* bytes, size_t size) const;
  Status Read(uint64_t offset, void* bytes, size_t size) const;

 private:
  ScratchFile(int fd, std::filesystem::path folder) : fd_(fd), folder_(std::move(folder)) {}
  int fd_ = -1;
  std::filesystem::path folder_;  // for messages
};

}  // namespace mesocap

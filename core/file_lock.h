// An exclusive lock on a file of its own (flock), for work that several jobs may reach at once:
// the shard that computes what all shards share, a shard run twice. Released with the object
// (and by the kernel with a killed process).
#pragma once

#include <filesystem>

#include "core/status.h"

namespace mesocap {

class FileLock {
 public:
  // Creates `path` if missing and locks it; `wait`: block until free, else fail at once with
  // "`path` is held by another job".
  static StatusOr<FileLock> Exclusive(const std::filesystem::path& path, bool wait);
  FileLock(FileLock&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }
  FileLock& operator=(FileLock&&) = delete;
  ~FileLock();

 private:
  FileLock() = default;
  int fd_ = -1;
};

}  // namespace mesocap

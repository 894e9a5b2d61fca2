#include "core/file_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/cancel.h"

namespace mesocap {

StatusOr<FileLock> FileLock::Exclusive(const std::filesystem::path& path, bool wait) {
  FileLock lock;
  lock.fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lock.fd_ < 0) return Status::Error(path.string() + ": cannot create: " + std::strerror(errno));
  // Polled rather than blocking, so Ctrl-C still stops a waiting job.
  while (::flock(lock.fd_, LOCK_EX | LOCK_NB) != 0) {
    if (errno != EWOULDBLOCK) return Status::Error(path.string() + ": cannot lock: " + std::strerror(errno));
    if (!wait) return Status::Error(path.string() + " is held by another job");
    if (CancelRequested()) return Status::Cancelled();
    ::usleep(50000);
  }
  return lock;
}

FileLock::~FileLock() {
  if (fd_ >= 0) ::close(fd_);
}

}  // namespace mesocap

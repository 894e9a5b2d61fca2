#include "core/scratch_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>

#include "core/atomic_file.h"

namespace mesocap {
namespace fs = std::filesystem;

StatusOr<ScratchFile> ScratchFile::Create(const fs::path& folder) {
  const fs::path dir = folder.empty() ? fs::path(".") : folder;
  int fd = ::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
  if (fd < 0 && (errno == EOPNOTSUPP || errno == EISDIR || errno == EINVAL)) {
    std::string name = (dir / ".mesocap-scratch-XXXXXX").string();
    fd = ::mkostemp(name.data(), O_CLOEXEC);
    if (fd >= 0) ::unlink(name.c_str());
  }
  if (fd < 0) return Status::Error(dir.string() + ": cannot create a scratch file: " + std::strerror(errno));
  return ScratchFile(fd, dir);
}

ScratchFile& ScratchFile::operator=(ScratchFile&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = other.fd_, folder_ = std::move(other.folder_);
    other.fd_ = -1;
  }
  return *this;
}

ScratchFile::~ScratchFile() {
  if (fd_ >= 0) ::close(fd_);
}

Status ScratchFile::Write(uint64_t offset, const void* bytes, size_t size) const {
  if (const int error = WriteAllAt(fd_, bytes, size, offset))
    return Status::Error(folder_.string() + ": cannot write a scratch file: " + std::strerror(error));
  return Status::Ok();
}

Status ScratchFile::Read(uint64_t offset, void* bytes, size_t size) const {
  char* p = static_cast<char*>(bytes);
  while (size > 0) {
    const ssize_t n = ::pread(fd_, p, size, off_t(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      return Status::Error(folder_.string() + ": cannot read back a scratch file: " +
                           (n < 0 ? std::strerror(errno) : "it is shorter than what was written"));
    p += n, size -= size_t(n), offset += uint64_t(n);
  }
  return Status::Ok();
}

}  // namespace mesocap

#include "core/atomic_file.h"

#include "core/provenance.h"

#include <signal.h>

#include <fmt/format.h>

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>

namespace mesocap {
namespace fs = std::filesystem;

namespace {

std::string ErrnoText() { return std::strerror(errno); }

// "PID@HOST", what temp and staging names carry to say which run made them.
std::string RunTag() { return fmt::format("{}@{}", ::getpid(), HostName()); }

// Whether `owner` ("PID@HOST", or "PID" as older versions wrote it) names a process of this host
// that has ended: what it left may go. A live process may be another run at work; one of another
// user answers EPERM; a run on another host sharing the folder cannot be judged here: all stay.
bool ProcessEnded(const std::string& owner) {
  const size_t at = owner.find('@');
  const std::string pid_text = owner.substr(0, at);
  if (at != std::string::npos && owner.substr(at + 1) != HostName()) return false;
  if (pid_text.empty() || pid_text.size() > 9 || pid_text.find_first_not_of("0123456789") != std::string::npos)
    return false;
  const pid_t pid = pid_t(std::stol(pid_text));
  return pid != ::getpid() && ::kill(pid, 0) != 0 && errno == ESRCH;
}

// Removes the temps that killed runs of this host left in `folder` (`.NAME.tmpPID@HOST_N...`,
// also nested ones such as `..NAME.tmpPID@HOST_0.tmpPID@HOST_1.ext` of a file set's member): a run interrupted by Ctrl-C
// or the machine stopping cannot remove its own. Once per folder and process, so a folder written
// file by file is listed once.
void RemoveStaleTempsOnce(const fs::path& folder) {
  static std::mutex mutex;
  static std::set<fs::path> swept;
  const std::lock_guard lock(mutex);
  if (!swept.insert(folder).second) return;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder.empty() ? fs::path(".") : folder, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.front() != '.') continue;
    // A file set's backup (`.NAME.old-PID@HOST`, OutputFileSet::Commit) of a run killed between its
    // renames: put back where the new file never arrived, else no longer needed.
    if (const size_t old = name.rfind(".old-"); old != std::string::npos && old > 1 && entry.is_regular_file(ec)) {
      if (ProcessEnded(name.substr(old + 5))) {
        const fs::path final_path = entry.path().parent_path() / name.substr(1, old - 1);
        if (!fs::exists(final_path, ec)) fs::rename(entry.path(), final_path, ec);
        else fs::remove(entry.path(), ec);
      }
      continue;
    }
    for (size_t tag = name.find(".tmp"); tag != std::string::npos; tag = name.find(".tmp", tag + 1)) {
      const size_t pid_end = name.find('_', tag);
      if (pid_end == std::string::npos) break;
      if (ProcessEnded(name.substr(tag + 4, pid_end - tag - 4))) {
        fs::remove_all(entry.path(), ec);
        break;
      }
    }
  }
}

fs::path TempPathFor(const fs::path& path) {
  RemoveStaleTempsOnce(path.parent_path());
  static std::atomic<unsigned> counter{0};
  // {fmt}, not string operator+: GCC 12 warns falsely (-Wrestrict) on "." + std::string.
  return path.parent_path() /
         fmt::format(".{}.tmp{}_{}{}", path.stem().string(), RunTag(), counter++, path.extension().string());
}

Status WriteAll(int fd, std::string_view text, const fs::path& path) {
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      return Status::Error(path.string() + ": write failed: " + ErrnoText());
    }
    done += size_t(n);
  }
  return Status::Ok();
}

}  // namespace

Status SyncPath(const fs::path& path) {
  const int fd = ::open(path.empty() ? "." : path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return Status::Error(path.string() + ": cannot open to sync: " + ErrnoText());
  const int rc = ::fsync(fd);
  const int saved = errno;
  ::close(fd);
  if (rc != 0 && saved != EINVAL) {  // some file systems cannot fsync folders
    errno = saved;
    return Status::Error(path.string() + ": fsync failed: " + ErrnoText());
  }
  return Status::Ok();
}

// `.NAME.TAG-PID@HOST` beside `path`: hidden, and unique to this process.
static fs::path HiddenSibling(const fs::path& path, const char* tag) {
  return path.parent_path() / fmt::format(".{}.{}-{}", path.filename().string(), tag, RunTag());
}

fs::path StagingFolderFor(const fs::path& out) { return HiddenSibling(out, "partial"); }

Status PublishStagingFolder(const fs::path& staging, const fs::path& out) {
  std::error_code ec;
  if (fs::exists(out, ec)) fs::remove(out, ec);  // an empty folder (callers check before they start)
  fs::rename(staging, out, ec);
  if (ec) return Status::Error(out.string() + ": cannot move the finished folder into place: " + ec.message());
  return SyncPath(out.parent_path());
}

StagingFolder::StagingFolder(fs::path out, fs::path staging) : out_(std::move(out)), staging_(std::move(staging)) {}

StagingFolder::StagingFolder(StagingFolder&& other) noexcept
    : out_(std::move(other.out_)), staging_(std::move(other.staging_)), published_(other.published_) {
  other.published_ = true;  // the moved-from object owns nothing
}

StagingFolder::~StagingFolder() {
  if (published_ || staging_.empty()) return;
  std::error_code ec;
  fs::remove_all(staging_, ec);
}

// Removes `.NAME.partial-PID@HOST` and `.NAME.old-PID@HOST` beside `out` whose process on this
// host has ended: what a killed run left (a live PID may be another run at work, and a run on
// another host sharing the folder cannot be judged: both are left alone).
static void RemoveStaleSiblings(const fs::path& out) {
  const std::string name = out.filename().string();
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(out.parent_path(), ec)) {
    const std::string sibling = entry.path().filename().string();
    for (const char* tag : {"partial", "old"}) {
      const std::string prefix = fmt::format(".{}.{}-", name, tag);
      if (sibling.rfind(prefix, 0) != 0) continue;
      if (ProcessEnded(sibling.substr(prefix.size()))) fs::remove_all(entry.path(), ec);
    }
  }
}

StatusOr<StagingFolder> StagingFolder::Begin(const fs::path& out_path) {
  fs::path out = fs::absolute(out_path).lexically_normal();
  if (out.filename().empty()) out = out.parent_path();  // "dir/" names "dir"
  StagingFolder folder(out, StagingFolderFor(out));
  RemoveStaleSiblings(out);
  std::error_code ec;
  fs::remove_all(folder.staging_, ec);  // left by an earlier run of this process id
  fs::create_directories(folder.staging_, ec);
  if (ec) return Status::Error(folder.staging_.string() + ": cannot create: " + ec.message());
  return folder;
}

Status StagingFolder::Publish(bool replace) {
  std::error_code ec;
  fs::path old;
  if (replace && fs::exists(out_, ec) && !(fs::is_directory(out_, ec) && fs::is_empty(out_, ec))) {
    old = HiddenSibling(out_, "old");
    fs::remove_all(old, ec);
    fs::rename(out_, old, ec);
    if (ec) return Status::Error(out_.string() + ": cannot move the previous folder aside: " + ec.message());
  }
  if (Status st = PublishStagingFolder(staging_, out_); !st.ok()) {
    if (!old.empty()) fs::rename(old, out_, ec);  // put the previous outputs back
    return st;
  }
  published_ = true;
  if (!old.empty()) fs::remove_all(old, ec);
  return Status::Ok();
}

Status WriteFileAtomically(const fs::path& path, const std::function<Status(const fs::path&)>& write) {
  const fs::path temp = TempPathFor(path);
  std::error_code ec;
  Status st = write(temp);
  if (st.ok()) st = SyncPath(temp);
  if (st.ok()) {
    fs::rename(temp, path, ec);
    if (ec) st = Status::Error(path.string() + ": cannot rename into place: " + ec.message());
  }
  if (!st.ok()) {
    fs::remove(temp, ec);
    return st;
  }
  return SyncPath(path.parent_path());
}

Status WriteTextAtomically(const fs::path& path, std::string_view text) {
  return WriteFileAtomically(path, [&](const fs::path& temp) -> Status {
    const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) return Status::Error(path.string() + ": cannot create: " + ErrnoText());
    Status st = WriteAll(fd, text, path);
    if (::close(fd) != 0 && st.ok()) st = Status::Error(path.string() + ": close failed: " + ErrnoText());
    return st;
  });
}

Status AppendLineDurably(const fs::path& path, std::string_view line) {
  const bool existed = fs::exists(path);
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) return Status::Error(path.string() + ": cannot open for append: " + ErrnoText());
  std::string text;
  // A crash mid-append leaves a last line without its newline: end it, so this line stays whole.
  if (existed) {
    char last = '\n';
    const int rfd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (rfd >= 0) {
      const off_t size = ::lseek(rfd, 0, SEEK_END);
      if (size > 0 && ::pread(rfd, &last, 1, size - 1) != 1) last = '\n';
      ::close(rfd);
    }
    if (last != '\n') text.push_back('\n');
  }
  text.append(line);
  text.push_back('\n');
  Status st = WriteAll(fd, text, path);
  if (st.ok() && ::fsync(fd) != 0) st = Status::Error(path.string() + ": fsync failed: " + ErrnoText());
  ::close(fd);
  if (st.ok() && !existed) st = SyncPath(path.parent_path());
  return st;
}

OutputFileSet::~OutputFileSet() {
  std::error_code ec;
  for (const auto& [temp, path] : staged_) fs::remove(temp, ec);
}

Status OutputFileSet::Stage(const fs::path& path, const std::function<Status(const fs::path&)>& write) {
  const fs::path temp = TempPathFor(path);
  staged_.emplace_back(temp, path);
  Status st = write(temp);
  if (st.ok()) st = SyncPath(temp);
  if (st.ok()) return st;
  std::string message = st.message();
  for (size_t at = message.find(temp.string()); at != std::string::npos; at = message.find(temp.string(), at))
    message.replace(at, temp.string().size(), path.string());
  return Status::Error(message);
}

Status OutputFileSet::Commit() {
  // Each file already there is first moved aside to a hidden backup (.NAME.old-PID@HOST), so a
  // failed rename puts every earlier file of the set back: the set appears whole or not at all.
  // A run killed between the renames leaves backups, which the next write into the folder puts
  // back (where the new file is missing) or removes (RemoveStaleTempsOnce).
  struct Placed {
    fs::path path, backup;
    bool had_old = false;
  };
  std::vector<Placed> placed;
  std::error_code ec;
  const auto roll_back = [&placed] {
    std::error_code ignored;
    for (auto it = placed.rbegin(); it != placed.rend(); ++it) {
      if (it->had_old) fs::rename(it->backup, it->path, ignored);
      else fs::remove(it->path, ignored);
    }
  };
  for (const auto& [temp, path] : staged_) {
    Placed p{path, HiddenSibling(path, "old"), fs::exists(path, ec)};
    if (p.had_old) {
      fs::rename(path, p.backup, ec);
      if (ec) {
        roll_back();
        return Status::Error(path.string() + ": cannot move the previous file aside: " + ec.message());
      }
    }
    fs::rename(temp, path, ec);
    if (ec) {
      const std::string why = ec.message();
      if (p.had_old) fs::rename(p.backup, path, ec);
      roll_back();
      return Status::Error(path.string() + ": cannot rename into place: " + why + " (the set's other files were put back)");
    }
    placed.push_back(p);
  }
  staged_.clear();
  std::set<fs::path> folders;
  for (const Placed& p : placed) {
    if (p.had_old) fs::remove(p.backup, ec);
    folders.insert(p.path.parent_path());
  }
  for (const fs::path& folder : folders) MESOCAP_RETURN_IF_ERROR(SyncPath(folder));
  return Status::Ok();
}

StatusOr<std::string> ReadTextFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::Error(path.string() + ": cannot open");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) return Status::Error(path.string() + ": read failed");
  return ss.str();
}

OutputFile::OutputFile(const fs::path& path) {
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) error_ = errno;
}

OutputFile::~OutputFile() {
  if (fd_ >= 0) ::close(fd_);
}

int WriteAllAt(int fd, const void* bytes, size_t size, uint64_t offset) {
  const char* p = static_cast<const char*>(bytes);
  while (size > 0) {
    const ssize_t n = ::pwrite(fd, p, size, off_t(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return n < 0 ? errno : EIO;
    p += n, size -= size_t(n), offset += uint64_t(n);
  }
  return 0;
}

void OutputFile::WriteAt(uint64_t offset, const void* bytes, size_t size) {
  if (!ok()) return;
  if (const int error = WriteAllAt(fd_, bytes, size, offset)) error_ = error;
}

void OutputFile::StartWriteBack(uint64_t offset, size_t size) {
#ifdef __linux__
  if (ok()) ::sync_file_range(fd_, off64_t(offset), off64_t(size), SYNC_FILE_RANGE_WRITE);
#endif
}

bool OutputFile::Close() {
  if (fd_ >= 0 && ::close(fd_) != 0 && error_ == 0) error_ = errno;
  fd_ = -1;
  if (error_ != 0) errno = error_;
  return error_ == 0;
}

}  // namespace mesocap

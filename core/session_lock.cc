#include "core/session_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/provenance.h"
#include "core/session_layout.h"

namespace mesocap {
namespace fs = std::filesystem;

namespace {

constexpr const char* kHolderVariable = "MESOCAP_SESSION_LOCK";

// The parent of `pid` (from /proc), or 0.
pid_t ParentOf(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
  const size_t close = text.rfind(')');  // the command name may hold spaces and parentheses
  if (close == std::string::npos) return 0;
  std::istringstream rest(text.substr(close + 1));
  std::string state;
  pid_t parent = 0;
  rest >> state >> parent;
  return parent;
}

bool IsAncestor(pid_t ancestor) {
  for (pid_t p = ::getppid(); p > 1; p = ParentOf(p))
    if (p == ancestor) return true;
  return false;
}

// Whether an ancestor of this process holds the lock of `session` and said so in the environment.
bool UnderAncestorsLock(const fs::path& session) {
  const char* value = std::getenv(kHolderVariable);
  if (!value) return false;
  const std::string text = value;
  const size_t bar = text.rfind('|');
  if (bar == std::string::npos || fs::path(text.substr(0, bar)) != session) return false;
  const Json holder = SessionLock::Holder(session);
  const pid_t pid = pid_t(std::atol(text.c_str() + bar + 1));
  return holder.is_object() && holder.value("pid", 0) == pid && holder.value("host", "") == HostName() && IsAncestor(pid);
}

std::string Describe(const fs::path& session, const Json& holder) {
  if (!holder.is_object())
    return session.string() + " is in use by another mesocap command (shards of a sharded stage hold its lock shared)";
  return session.string() + " is being written by mesocap " + holder.value("command", "?") + " (pid " +
         std::to_string(holder.value("pid", 0)) + " on host " + holder.value("host", "?") + ", since " +
         holder.value("since", "?") + "); wait for it to finish, or stop it";
}

}  // namespace

Json SessionLock::Holder(const fs::path& session) {
  const fs::path path = SessionLayout(session).lock();
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return nullptr;
  const bool free = ::flock(fd, LOCK_SH | LOCK_NB) == 0;  // a reader's probe: shared, released at once
  if (free) ::flock(fd, LOCK_UN);
  std::string text(4096, '\0');
  const ssize_t n = ::pread(fd, text.data(), text.size(), 0);
  ::close(fd);
  if (free || n <= 0) return nullptr;
  text.resize(size_t(n));
  Json holder = Json::parse(text, nullptr, false);
  return holder.is_discarded() ? Json(Json::object()) : holder;
}

StatusOr<SessionLock> SessionLock::Acquire(const fs::path& session_path, const std::string& command) {
  const fs::path session = fs::absolute(session_path).lexically_normal();
  SessionLock lock;
  if (UnderAncestorsLock(session)) return lock;
  const fs::path path = SessionLayout(session).lock();
  MESOCAP_RETURN_IF_ERROR(lock.Take(session, LOCK_EX));
  const std::string holder =
      Json{{"command", command}, {"pid", int(::getpid())}, {"host", HostName()}, {"since", UtcNowIso8601()}}.dump();
  if (::ftruncate(lock.fd_, 0) != 0 || ::pwrite(lock.fd_, holder.data(), holder.size(), 0) != ssize_t(holder.size()))
    return Status::Error(path.string() + ": cannot record the lock's holder: " + std::strerror(errno));
  ::setenv(kHolderVariable, (session.string() + "|" + std::to_string(::getpid())).c_str(), 1);
  return lock;
}

Status SessionLock::Take(const fs::path& session, int operation) {
  const fs::path path = SessionLayout(session).lock();
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) return Status::Error(path.string() + ": cannot create the session lock: " + std::strerror(errno));
  // A few tries 10 ms apart: a reader's probe (Holder) holds a shared lock for an instant.
  for (int attempt = 0; ::flock(fd_, operation | LOCK_NB) != 0; ++attempt) {
    if (errno != EWOULDBLOCK) return Status::Error(path.string() + ": cannot lock: " + std::strerror(errno));
    if (attempt == 10) return Status::Error(Describe(session, Holder(session)));
    ::usleep(10000);
  }
  return Status::Ok();
}

StatusOr<SessionLock> SessionLock::AcquireShared(const fs::path& session_path) {
  const fs::path session = fs::absolute(session_path).lexically_normal();
  SessionLock lock;
  if (UnderAncestorsLock(session)) return lock;
  MESOCAP_RETURN_IF_ERROR(lock.Take(session, LOCK_SH));
  return lock;
}

SessionLock::SessionLock(SessionLock&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }

SessionLock::~SessionLock() {
  if (fd_ < 0) return;
  ::unsetenv(kHolderVariable);
  ::close(fd_);  // releases the flock; the file stays (removing it would race a waiting opener)
}

}  // namespace mesocap

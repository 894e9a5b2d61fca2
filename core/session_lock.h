// One writer per session: every command that writes into a session folder (capture, calibrate,
// process, export) holds SESSION/.mesocap.lock (flock) while it runs. A second writer is refused
// with a message naming the holder (command, pid, host, since when); readers take no lock and are
// never blocked. The lock goes with the process (a killed run leaves nothing to clean). flock
// works across hosts on NFSv4 and local file systems.
//
// A holder may run work under its own lock: it exports MESOCAP_SESSION_LOCK (the session's
// absolute path and its pid) to its children, and a child's Acquire of that session then
// succeeds without taking the lock while the holder is its ancestor.
#pragma once

#include <filesystem>
#include <string>

#include "core/json.h"
#include "core/status.h"

namespace mesocap {

class SessionLock {
 public:
  // Takes the lock of the session folder `session` for `command` ("process", "export", ...), or
  // fails: "SESSION is being written by mesocap process (pid 123 on host lab-1, since ...)".
  static StatusOr<SessionLock> Acquire(const std::filesystem::path& session, const std::string& command);
  // A shard of a sharded stage (docs/workflow.md): many hold the lock shared at once, each writing
  // only its own part; a writer's Acquire is refused while any does, and they are refused while a
  // writer holds it.
  static StatusOr<SessionLock> AcquireShared(const std::filesystem::path& session);
  // The holder's record (command, pid, host, since) of a locked session, or null when nobody holds it.
  static Json Holder(const std::filesystem::path& session);

  SessionLock(SessionLock&& other) noexcept;
  SessionLock& operator=(SessionLock&&) = delete;
  ~SessionLock();
  // False for a child working under an ancestor's lock.
  bool owns_lock() const { return fd_ >= 0; }

 private:
  SessionLock() = default;
  Status Take(const std::filesystem::path& session, int flock_operation);  // LOCK_EX or LOCK_SH
  int fd_ = -1;
};

}  // namespace mesocap

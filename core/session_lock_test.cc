#include "core/session_lock.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>

#include <gtest/gtest.h>

#include "core/provenance.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

TEST(SessionLock, ASecondWriterIsRefusedWithTheHolderNamed) {
  const std::filesystem::path session = testing::MakeTempDir();
  {
    auto first = SessionLock::Acquire(session, "process");
    ASSERT_TRUE(first.ok()) << first.status().message();
    EXPECT_TRUE(first->owns_lock());
    auto second = SessionLock::Acquire(session, "export");
    ASSERT_FALSE(second.ok());
    const std::string message = second.status().message();
    EXPECT_NE(message.find("mesocap process"), std::string::npos) << message;
    EXPECT_NE(message.find("pid " + std::to_string(::getpid())), std::string::npos) << message;
    EXPECT_NE(message.find("host " + HostName()), std::string::npos) << message;
    const Json holder = SessionLock::Holder(session);
    ASSERT_TRUE(holder.is_object());
    EXPECT_EQ(holder.value("command", ""), "process");
  }
  // Released with its holder: nobody holds it, and the next writer gets it.
  EXPECT_TRUE(SessionLock::Holder(session).is_null());
  auto again = SessionLock::Acquire(session, "export");
  EXPECT_TRUE(again.ok()) << again.status().message();
}

TEST(SessionLock, ShardsShareTheLockAndExcludeWriters) {
  const std::filesystem::path session = testing::MakeTempDir();
  {
    auto shard1 = SessionLock::AcquireShared(session);
    auto shard2 = SessionLock::AcquireShared(session);
    ASSERT_TRUE(shard1.ok()) << shard1.status().message();
    ASSERT_TRUE(shard2.ok()) << shard2.status().message();
    auto writer = SessionLock::Acquire(session, "process");
    ASSERT_FALSE(writer.ok());
    EXPECT_NE(writer.status().message().find("shards of a sharded stage"), std::string::npos) << writer.status().message();
  }
  {
    auto writer = SessionLock::Acquire(session, "process");
    ASSERT_TRUE(writer.ok()) << writer.status().message();
    auto shard = SessionLock::AcquireShared(session);
    ASSERT_FALSE(shard.ok());
    EXPECT_NE(shard.status().message().find("mesocap process"), std::string::npos) << shard.status().message();
  }
}

// Runs `SessionLock::Acquire` in a forked child; its exit code: 0 taken as a guest (no lock of its
// own), 1 refused, 2 taken with a lock of its own.
int AcquireInChild(const std::filesystem::path& session, bool keep_environment) {
  const pid_t child = ::fork();
  if (child == 0) {
    if (!keep_environment) ::unsetenv("MESOCAP_SESSION_LOCK");
    auto lock = SessionLock::Acquire(session, "calibrate");
    std::_Exit(!lock.ok() ? 1 : lock->owns_lock() ? 2 : 0);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(SessionLock, AHolderRunsWorkUnderItsLockAndNobodyElseDoes) {
  const std::filesystem::path session = testing::MakeTempDir() / "session", other = session.parent_path() / "other";
  std::filesystem::create_directories(session);
  std::filesystem::create_directories(other);
  auto lock = SessionLock::Acquire(session, "process");
  ASSERT_TRUE(lock.ok()) << lock.status().message();
  EXPECT_EQ(AcquireInChild(session, true), 0);   // its child, told by the environment
  EXPECT_EQ(AcquireInChild(session, false), 1);  // a process not told is refused
  EXPECT_EQ(AcquireInChild(other, true), 2);  // another session: its own lock
}

}  // namespace
}  // namespace mesocap

// Ctrl-C through the real CLI, for the tests of tests/e2e/cancel*_test.cc: start a command, send
// SIGINT at a moment drawn after start-up, check that it ended with exit code 3 leaving nothing
// half-made, and that the same command then completes.
#pragma once

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "tests/testing.h"

namespace mesocap {

namespace fs = std::filesystem;

struct Interrupted {
  bool exited = false;
  int code = -1;
  double seconds_to_exit = 0;
};

// Starts `mesocap ARGS`, sends SIGINT after `delay_s`, waits at most 30 s for it to end.
inline Interrupted InterruptAfter(const std::string& args, double delay_s) {
  const std::string command = "exec " + testing::MesocapBinary() + " " + args + " >/dev/null 2>&1";
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::execl("/bin/sh", "sh", "-c", command.c_str(), nullptr);
    ::_exit(127);
  }
  std::this_thread::sleep_for(std::chrono::duration<double>(delay_s));
  ::kill(pid, SIGINT);
  const auto sent = std::chrono::steady_clock::now();
  Interrupted r;
  int status = 0;
  while (std::chrono::steady_clock::now() - sent < std::chrono::seconds(30)) {
    if (::waitpid(pid, &status, WNOHANG) == pid) {
      r.exited = WIFEXITED(status);
      r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
      r.seconds_to_exit = std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
      return r;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ::kill(pid, SIGKILL);
  ::waitpid(pid, &status, 0);
  return r;
}

// Hidden staging folders, temps, backups and scratch files of a run (".NAME.partial-...",
// ".NAME.tmp...", ".NAME.old-...", ".mesocap-scratch-...") in `dir`.
inline std::vector<std::string> LeftBehind(const fs::path& dir) {
  std::vector<std::string> left;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.find(".partial-") != std::string::npos || name.find(".tmp") != std::string::npos ||
        name.find(".old-") != std::string::npos || name.find(".mesocap-scratch-") != std::string::npos)
      left.push_back(name);
  }
  return left;
}

// A delay drawn from [from, to) seconds, fixed by the test's name.
inline double DrawDelay(double from, double to) {
  std::mt19937 rng(testing::SeedFromTestName());
  return std::uniform_real_distribution<double>(from, to)(rng);
}

inline void ExpectCancelledCleanlyThenCompletes(const std::string& args, const fs::path& work, double delay_s) {
  const Interrupted r = InterruptAfter(args, delay_s);
  ASSERT_TRUE(r.exited) << "did not end within 30 s of SIGINT (interrupted after " << delay_s << " s)";
  EXPECT_EQ(r.code, 3) << "interrupted after " << delay_s << " s: " << args;
  std::printf("%s: interrupted after %.2f s, exited %.2f s after SIGINT\n", args.substr(0, args.find(' ')).c_str(),
              delay_s, r.seconds_to_exit);
  EXPECT_TRUE(LeftBehind(work).empty()) << LeftBehind(work).front();
  std::string out;
  EXPECT_EQ(testing::RunMesocap(args, &out), 0) << out;
  EXPECT_TRUE(LeftBehind(work).empty());
}

}  // namespace mesocap

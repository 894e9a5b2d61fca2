#include "tests/testing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <iterator>
#include <cstdio>
#include <cstdlib>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

namespace mesocap::testing {

std::string CurrentTestName() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return info ? std::string(info->test_suite_name()) + "." + info->name() : "no_test";
}

namespace {

// Removes the folders MakeTempDir made once their owner passed: a test's at its end, a suite's
// (made outside any test) at the program's end. A failure keeps them to look at, and so does
// MESOCAP_KEEP_TEST_FILES; otherwise every run would leave its renders behind in /tmp.
class TempDirSweeper : public ::testing::EmptyTestEventListener {
 public:
  static TempDirSweeper& Installed() {
    static TempDirSweeper* sweeper = [] {
      auto* s = new TempDirSweeper;
      ::testing::UnitTest::GetInstance()->listeners().Append(s);  // owned by gtest from here
      return s;
    }();
    return *sweeper;
  }
  void Add(const std::filesystem::path& dir) {
    (::testing::UnitTest::GetInstance()->current_test_info() ? test_dirs_ : program_dirs_).push_back(dir);
  }
  void OnTestEnd(const ::testing::TestInfo& info) override { Sweep(&test_dirs_, info.result()->Passed()); }
  void OnTestProgramEnd(const ::testing::UnitTest& unit) override { Sweep(&program_dirs_, unit.Passed()); }

 private:
  static void Sweep(std::vector<std::filesystem::path>* dirs, bool passed) {
    if (passed && !std::getenv("MESOCAP_KEEP_TEST_FILES"))
      for (const auto& dir : *dirs) {
        std::error_code ec;
        std::filesystem::remove_all(dir, ec);
      }
    dirs->clear();
  }
  std::vector<std::filesystem::path> test_dirs_, program_dirs_;
};

}  // namespace

std::filesystem::path MakeTempDir() {
  static int counter = 0;
  std::string name = CurrentTestName();
  std::replace(name.begin(), name.end(), '/', '_');  // parameterised tests: "Formats/Suite.Test/0"
  const auto dir = std::filesystem::temp_directory_path() /
                   ("mesocap_test_" + name + "_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  TempDirSweeper::Installed().Add(dir);
  return dir;
}

uint32_t SeedFromTestName() {
  uint32_t h = 2166136261u;  // FNV-1a
  for (const char c : CurrentTestName()) h = (h ^ uint8_t(c)) * 16777619u;
  return h;
}

std::string MesocapBinary() {
  const char* bin = std::getenv("MESOCAP_BIN");
  return bin ? bin : "mesocap";
}

int RunCommand(const std::string& command, std::string* output) {
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return -1;
  std::array<char, 4096> buf;
  std::string out;
  size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) out.append(buf.data(), n);
  const int status = ::pclose(pipe);
  if (output) *output = out;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

int RunMesocap(const std::string& args, std::string* output) {
  return RunCommand(MesocapBinary() + " " + args + " 2>&1", output);
}

int ValidateGltf(const std::filesystem::path& gltf, std::string* output) {
  const char* source = std::getenv("MESOCAP_SOURCE_DIR");
  if (!source) {
    if (output) *output = "MESOCAP_SOURCE_DIR is not set (ctest sets it)";
    return 2;
  }
  const std::filesystem::path script = std::filesystem::path(source) / "scripts" / "validate-gltf.mjs";
  return RunCommand("node " + script.string() + " " + gltf.string() + " 2>&1", output);
}

std::string HeadlessDom(const std::string& url, std::string* log) {
  // --no-sandbox: tests may run as root; SwiftShader: WebGL without a GPU; virtual time lets the
  // page's promises settle before the DOM is dumped.
  // A profile of its own: no dependence on $HOME or on another run's state.
  const std::filesystem::path scratch = std::filesystem::temp_directory_path() / ("chromium-" + std::to_string(::getpid()));
  const std::string err = scratch.string() + ".log";
  std::string dom;
  RunCommand("chromium --headless --no-sandbox --disable-gpu --use-angle=swiftshader --enable-unsafe-swiftshader "
             "--user-data-dir=" + scratch.string() + " --virtual-time-budget=20000 --dump-dom '" + url + "' 2>" + err,
             &dom);
  std::error_code ec;
  std::filesystem::remove_all(scratch, ec);
  if (log) {
    std::ifstream in(err);
    *log = std::string(std::istreambuf_iterator<char>(in), {});
  }
  std::filesystem::remove(err);
  return dom;
}

}  // namespace mesocap::testing

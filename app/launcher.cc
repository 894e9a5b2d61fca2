// mesocap: the executable users run. Every command's work lives in mesocap-commands (installed
// beside it), which links OpenImageIO, OpenCV, Ceres and libgphoto2: loading those ~280 shared
// libraries takes 0.4 s before main. --version and --help (of the program or of a command) are
// answered here from text the build captured from mesocap-commands itself (app/help_text_gen.cc),
// in about a millisecond; anything else replaces this process with mesocap-commands, same
// arguments, so its output and exit code are the command's own.
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstring>
#include <string>

#include "app/help_text.h"

namespace {

bool IsHelp(const char* arg) { return std::strcmp(arg, "--help") == 0 || std::strcmp(arg, "-h") == 0; }

// The help or version text this command line asks for, or nullptr.
const char* CannedAnswer(int argc, char** argv) {
  namespace text = mesocap::app::help_text;
  if (argc == 2 && std::strcmp(argv[1], "--version") == 0) return text::kVersion;
  if (argc == 2 && IsHelp(argv[1])) return text::kTop;
  if (argc == 3 && IsHelp(argv[2]))
    for (const auto& command : text::kCommands)
      if (std::strcmp(argv[1], command.name) == 0) return command.text;
  return nullptr;
}

// mesocap-commands in the folder this executable is in.
std::string CommandsExecutable() {
  char self[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  if (n <= 0) return "mesocap-commands";
  std::string path(self, size_t(n));
  return path.substr(0, path.rfind('/') + 1) + "mesocap-commands";
}

}  // namespace

int main(int argc, char** argv) {
  if (const char* answer = CannedAnswer(argc, argv)) {
    std::fputs(answer, stdout);
    return 0;
  }
  const std::string commands = CommandsExecutable();
  execv(commands.c_str(), argv);
  std::fprintf(stderr, "mesocap: cannot run %s: %s (a broken installation: reinstall mesocap)\n", commands.c_str(),
               std::strerror(errno));
  return 70;
}

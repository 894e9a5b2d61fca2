#include "core/provenance.h"

#include "core/stage_versions.h"

#include <unistd.h>

#include <chrono>
#include <ctime>

namespace mesocap {

namespace {
std::string& CommandLineStorage() {
  static std::string s;
  return s;
}
}  // namespace

const char* Version() { return MESOCAP_VERSION; }
const char* SourceRevision() { return MESOCAP_SOURCE_REVISION; }

std::string HostName() {
  char name[256] = {};
  if (::gethostname(name, sizeof(name) - 1) != 0 || !name[0]) return "localhost";
  return name;
}

void SetCommandLine(int argc, char** argv) {
  std::string s;
  for (int i = 0; i < argc; ++i) {
    if (i) s += ' ';
    s += argv[i];
  }
  CommandLineStorage() = s;
}

const std::string& CommandLine() { return CommandLineStorage(); }

std::string UtcIso8601(std::time_t time) {
  std::tm tm{};
  gmtime_r(&time, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::string UtcNowIso8601() { return UtcIso8601(std::chrono::system_clock::to_time_t(std::chrono::system_clock::now())); }

Json MakeProvenance(const Json& options) {
  return {{"program", "mesocap"}, {"version", Version()}, {"source_revision", SourceRevision()},
          {"stage_versions", StageVersions()}, {"command_line", CommandLine()},
          {"time_utc", UtcNowIso8601()}, {"options", options}};
}

}  // namespace mesocap

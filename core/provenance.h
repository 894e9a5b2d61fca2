// Every output folder records how it was made (mrcal): resolved options, command line,
// program version and time.
#pragma once

#include <ctime>
#include <string>

#include "core/json.h"

namespace mesocap {

// Version string from the build ("0.1.0").
const char* Version();
// The git revision the build was configured at ("3f2a1c0d9e8b", "+dirty" when it had local
// changes, "unknown" outside a git tree).
const char* SourceRevision();

// The command line of this run, set once by the commands module (app/commands_module.cc).
void SetCommandLine(int argc, char** argv);
const std::string& CommandLine();

// This machine's host name: what the session lock and the staging names record, so that a run on
// another host sharing the folder is never judged by this host's process table.
std::string HostName();

std::string UtcNowIso8601();
// A time (seconds since the epoch) as ISO 8601 UTC, "2026-12-05T10:00:00Z".
std::string UtcIso8601(std::time_t time);

// {"program": "mesocap", "version", "command_line", "time_utc", "options": options}
Json MakeProvenance(const Json& options);

}  // namespace mesocap

// mesocap layout: the session layout (core/session_layout.h) as a program prints it, so a
// workflow or a web page never spells a session's paths itself. Text: one "name<TAB>path" line
// per file or folder, the paths joined to the session as given; --json: the layout's own JSON.
#include "app/layout_args.h"

#include <cstdio>
#include <filesystem>
#include <string>

#include "app/commands.h"
#include "core/json.h"
#include "core/session_layout.h"

namespace mesocap::app {
namespace {

// Every string leaf of `j` as "a.b.c<TAB>SESSION/path".
void PrintLeaves(const Json& j, const std::string& prefix, const std::filesystem::path& session) {
  for (const auto& [key, value] : j.items()) {
    const std::string name = prefix.empty() ? key : prefix + "." + key;
    if (value.is_object()) PrintLeaves(value, name, session);
    else if (value.is_string()) std::printf("%s\t%s\n", name.c_str(), (session / value.get<std::string>()).string().c_str());
  }
}

}  // namespace

int RunLayout(const LayoutArgs& args) {
  const SessionLayout layout(args.session);
  Json j = layout.ToJson();
  if (args.json) {
    std::printf("%s\n", j.dump(2).c_str());
    return kExitOk;
  }
  for (const char* header : {"format", "format_version", "root", "note"}) j.erase(header);
  PrintLeaves(j, "", args.session);
  return kExitOk;
}

}  // namespace mesocap::app

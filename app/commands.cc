#include "app/commands.h"

#include <cstdio>

namespace mesocap::app {

int Fail(const std::string& verb, const std::string& message, int code) {
  std::fprintf(stderr, "mesocap %s: %s\n", verb.c_str(), message.c_str());
  return code;
}

int Fail(const std::string& verb, const Status& status) {
  if (status.cancelled())
    return Fail(verb, "cancelled (Ctrl-C): stopped, and nothing half-written was left behind", kExitCancelled);
  return Fail(verb, status.message(), kExitFailure);
}

}  // namespace mesocap::app

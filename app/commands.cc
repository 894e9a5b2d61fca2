#include "app/commands.h"

#include <cstdio>

namespace mesocap::app {

int Fail(const std::string& verb, const std::string& message, int code) {
  std::fprintf(stderr, "mesocap %s: %s\n", verb.c_str(), message.c_str());
  return code;
}

}  // namespace mesocap::app

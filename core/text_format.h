// printf-style formatting into a std::string: report table cells, brief lines, reasons.
// {fmt}'s printf implementation: no length limit, and a mismatched argument is an exception
// rather than undefined behaviour.
#pragma once

#include <fmt/printf.h>

#include <string>

namespace mesocap {

template <typename... Args>
std::string Format(const char* format, const Args&... args) {
  return fmt::sprintf(format, args...);
}

}  // namespace mesocap

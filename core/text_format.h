// printf-style formatting into a std::string: report table cells, brief lines, reasons.
#pragma once

#include <string>

namespace mesocap {

std::string Format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

}  // namespace mesocap

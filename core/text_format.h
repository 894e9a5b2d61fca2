// printf-style formatting into a std::string: report table cells, brief lines, reasons.
// {fmt}'s printf implementation: no length limit, and a mismatched argument is an exception
// rather than undefined behaviour. And the two text clean-ups every reader of names and tags
// needs.
#pragma once

#include <fmt/printf.h>

#include <algorithm>
#include <cctype>
#include <string>

namespace mesocap {

template <typename... Args>
std::string Format(const char* format, const Args&... args) {
  return fmt::sprintf(format, args...);
}

// ASCII lower case (file extensions, camera and setting names).
inline std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

// Without leading and trailing blanks (spaces, tabs, line ends), as EXIF strings and settings
// arrive padded.
inline std::string Trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

}  // namespace mesocap

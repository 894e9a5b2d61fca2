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

// A brief report's list of skipped or rejected inputs: a line "\n  " + line_of(item) for each of
// the first `most` items, then "\n  ... and N more (see WHERE)" for the rest.
template <typename Items, typename LineOf>
std::string ListedLines(const Items& items, size_t most, const std::string& where, const LineOf& line_of) {
  std::string text;
  for (size_t i = 0; i < items.size() && i < most; ++i) text += "\n  " + line_of(items[i]);
  if (items.size() > most) text += "\n  ... and " + std::to_string(items.size() - most) + " more (see " + where + ")";
  return text;
}

}  // namespace mesocap

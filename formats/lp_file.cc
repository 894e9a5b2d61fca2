#include "formats/lp_file.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <string_view>

#include "core/atomic_file.h"

namespace mesocap {
namespace fs = std::filesystem;

namespace {

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r'))
    s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

bool ParseDouble(std::string_view text, double* value) {
  const std::string s(text);
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (errno != 0 || end == s.c_str() || *end != '\0' || !std::isfinite(v)) return false;
  *value = v;
  return true;
}

// Splits off the last whitespace-separated token of `line`; false if there is none.
bool PopLastToken(std::string_view* line, std::string_view* token) {
  *line = Trim(*line);
  if (line->empty()) return false;
  size_t start = line->find_last_of(" \t");
  start = start == std::string_view::npos ? 0 : start + 1;
  *token = line->substr(start);
  *line = line->substr(0, start);
  return true;
}

bool Exists(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

// The image a .lp line names: as written (relative to the .lp folder), with backslashes as
// separators, or by base name beside the .lp file.
bool ResolveImage(const fs::path& folder, const std::string& name, fs::path* resolved,
                  std::string* tried) {
  std::string slashed = name;
  for (char& c : slashed)
    if (c == '\\') c = '/';
  const bool windows_absolute = slashed.size() > 2 && slashed[1] == ':' && slashed[2] == '/';
  std::vector<fs::path> candidates;
  if (!windows_absolute) {
    const fs::path as_written(name);
    candidates.push_back(as_written.is_absolute() ? as_written : folder / as_written);
    if (slashed != name) {
      const fs::path p(slashed);
      candidates.push_back(p.is_absolute() ? p : folder / p);
    }
  }
  const size_t slash = slashed.find_last_of('/');
  const std::string base = slash == std::string::npos ? slashed : slashed.substr(slash + 1);
  if (!base.empty()) {
    const fs::path beside = folder / base;
    if (candidates.empty() || candidates.back() != beside) candidates.push_back(beside);
  }
  for (const fs::path& c : candidates) {
    if (Exists(c)) {
      *resolved = c;
      return true;
    }
  }
  tried->clear();
  for (size_t i = 0; i < candidates.size(); ++i) *tried += (i ? ", " : "") + candidates[i].string();
  if (!candidates.empty()) *resolved = candidates.front();
  return false;
}

}  // namespace

StatusOr<std::vector<LpEntry>> ReadLpFile(const fs::path& path, bool require_images_exist) {
  const std::string name = path.string();
  StatusOr<std::string> text = ReadTextFile(path);
  if (!text.ok()) return Status::Error(name + ": cannot open light-position file");
  const fs::path folder = path.parent_path();

  std::istringstream in(*text);
  std::string raw;
  int line_number = 0;
  long count = -1;
  std::vector<LpEntry> entries;
  while (std::getline(in, raw)) {
    ++line_number;
    std::string_view line = Trim(raw);
    if (line.empty()) continue;
    const std::string where = name + ":" + std::to_string(line_number) + ": ";
    if (count < 0) {
      double value;
      if (!ParseDouble(line, &value) || value != std::floor(value) || value < 1 || value > 1e6)
        return Status::Error(where + "the first line must be the number of images, found '" +
                             std::string(line.substr(0, 60)) + "'");
      count = long(value);
      continue;
    }
    if (long(entries.size()) == count)
      return Status::Error(where + "more image lines than the " + std::to_string(count) +
                           " the first line declares");
    std::string_view rest = line, tok[3];
    for (int i = 2; i >= 0; --i) {
      if (!PopLastToken(&rest, &tok[i]))
        return Status::Error(where + "expected 'filename x y z', found '" + std::string(line) +
                             "'");
    }
    rest = Trim(rest);
    if (rest.empty())
      return Status::Error(where + "expected 'filename x y z', found '" + std::string(line) + "'");
    Eigen::Vector3d d;
    for (int i = 0; i < 3; ++i) {
      if (!ParseDouble(tok[i], &d(i)))
        return Status::Error(where + "light coordinate '" + std::string(tok[i]) +
                             "' is not a number");
    }
    if (d.norm() < 1e-9) return Status::Error(where + "the light direction is (0, 0, 0)");
    LpEntry entry;
    entry.light_dir = d;
    std::string tried;
    const std::string image(rest);
    if (!ResolveImage(folder, image, &entry.image, &tried) && require_images_exist)
      return Status::Error(where + "image '" + image + "' not found (looked for " + tried + ")");
    entries.push_back(std::move(entry));
  }
  if (count < 0) return Status::Error(name + ": empty light-position file");
  if (long(entries.size()) != count)
    return Status::Error(name + ": the first line declares " + std::to_string(count) +
                         " images but the file lists " + std::to_string(entries.size()) +
                         " (truncated?)");
  return entries;
}

Status WriteLpFile(const fs::path& path, const std::vector<LpEntry>& entries) {
  const fs::path folder = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  std::string out = std::to_string(entries.size()) + "\n";
  for (const LpEntry& e : entries) {
    if (!e.light_dir.allFinite())
      return Status::Error(path.string() + ": cannot write a non-finite light direction for " +
                           e.image.string());
    const std::string image_text = e.image.string();
    if (image_text.empty() || image_text.find('\n') != std::string::npos)
      return Status::Error(path.string() + ": cannot write image name '" + image_text + "'");
    fs::path written = e.image;
    std::error_code ec;
    const fs::path abs_folder = fs::weakly_canonical(fs::absolute(folder, ec), ec);
    const fs::path abs_image = fs::weakly_canonical(fs::absolute(e.image, ec), ec);
    const fs::path rel = abs_image.lexically_relative(abs_folder);
    if (!ec && !rel.empty() && *rel.begin() != "..") written = rel;
    char buf[128];
    std::snprintf(buf, sizeof buf, " %.6f %.6f %.6f\n", e.light_dir.x(), e.light_dir.y(),
                  e.light_dir.z());
    out += written.string() + buf;
  }
  return WriteTextAtomically(path, out);
}

}  // namespace mesocap

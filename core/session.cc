#include "core/session.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "core/atomic_file.h"
#include "core/provenance.h"

namespace mesocap {
namespace fs = std::filesystem;

Json ShotRecord::ToJson() const {
  return {{"index", index}, {"kind", kind}, {"file", file}, {"time_utc", time_utc},
          {"settings", settings}, {"exif", exif}, {"flags", flags}};
}

ShotRecord ShotRecord::FromJson(const Json& j) {
  ShotRecord r;
  r.index = j.at("index").get<int>();
  r.kind = j.at("kind").get<std::string>();
  r.file = j.at("file").get<std::string>();
  r.time_utc = j.value("time_utc", "");
  r.settings = j.value("settings", Json::object());
  r.exif = j.value("exif", Json::object());
  r.flags = j.value("flags", std::vector<std::string>{});
  return r;
}

bool IsMissingOrEmptyDir(const fs::path& dir) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) return true;
  return fs::is_directory(dir, ec) && fs::is_empty(dir, ec);
}

StatusOr<Session> Session::Create(const fs::path& root, Json manifest) {
  if (!IsMissingOrEmptyDir(root))
    return Status::Error(root.string() + ": exists and is not empty; choose a new folder");
  std::error_code ec;
  fs::create_directories(root, ec);
  if (ec) return Status::Error(root.string() + ": cannot create folder: " + ec.message());
  Session s;
  s.root_ = root;
  manifest["format"] = "mesocap-session";
  manifest["format_version"] = 1;
  if (!manifest.contains("created_utc")) manifest["created_utc"] = UtcNowIso8601();
  s.manifest_ = std::move(manifest);
  MESOCAP_RETURN_IF_ERROR(WriteJsonFile(root / kManifestName, s.manifest_));
  return s;
}

StatusOr<Session> Session::Open(const fs::path& root) {
  Session s;
  s.root_ = root;
  const fs::path manifest_path = root / kManifestName;
  if (!fs::exists(manifest_path))
    return Status::Error(root.string() + ": not a mesocap session (no " + kManifestName + ")");
  auto manifest = ReadJsonFile(manifest_path);
  if (!manifest.ok()) return manifest.status();
  s.manifest_ = std::move(*manifest);
  const fs::path journal = root / kJournalName;
  if (fs::exists(journal)) {
    auto text = ReadTextFile(journal);
    if (!text.ok()) return text.status();
    std::istringstream lines(*text);
    std::string line;
    while (std::getline(lines, line)) {
      if (line.empty()) continue;
      try {
        const Json j = Json::parse(line);
        if (j.value("event", "") == "shot") s.shots_.push_back(ShotRecord::FromJson(j));
      } catch (const std::exception&) {
        ++s.torn_lines_;  // a crash mid-append cuts at most the last line
      }
    }
  }
  return s;
}

fs::path Session::DirFor(const std::string& kind) const {
  return root_ / (kind == "calib" ? "calib" : "shots");
}

Status Session::UpdateManifest(const Json& patch) {
  Json updated = manifest_;
  updated.merge_patch(patch);
  MESOCAP_RETURN_IF_ERROR(WriteJsonFile(root_ / kManifestName, updated));
  manifest_ = std::move(updated);
  return Status::Ok();
}

Status Session::RecordShot(const ShotRecord& record) {
  Json j = record.ToJson();
  j["event"] = "shot";
  MESOCAP_RETURN_IF_ERROR(AppendLineDurably(root_ / kJournalName, j.dump()));
  shots_.push_back(record);
  return Status::Ok();
}

std::vector<ShotRecord> Session::ShotsOfKind(const std::string& kind) const {
  std::vector<ShotRecord> out;
  std::copy_if(shots_.begin(), shots_.end(), std::back_inserter(out),
               [&](const ShotRecord& r) { return r.kind == kind; });
  return out;
}

int Session::NextIndex(const std::string& kind) const {
  int highest = 0;
  for (const auto& r : shots_)
    if (r.kind == kind) highest = std::max(highest, r.index);
  // Files present but never journaled (a crash between rename and append) also block reuse.
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(DirFor(kind), ec)) {
    int n = 0;
    const std::string name = entry.path().filename().string();
    if (std::sscanf(name.c_str(), (kind + "_%d").c_str(), &n) == 1) highest = std::max(highest, n);
  }
  return highest + 1;
}

std::string Session::ShotFileName(const std::string& kind, int index, const std::string& ext) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%s_%04d%s", kind.c_str(), index, ext.c_str());
  return (fs::path(kind == "calib" ? "calib" : "shots") / buf).string();
}

}  // namespace mesocap

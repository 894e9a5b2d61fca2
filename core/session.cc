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
  r.index = JsonInteger(JsonField(j, "", "index"), "index", 1, kMaxShotIndex);
  r.kind = JsonString(JsonField(j, "", "kind"), "kind");
  if (r.kind != "shot" && r.kind != "calib") throw JsonFieldError("kind '" + r.kind + "' must be shot or calib");
  r.file = JsonRelativePath(JsonField(j, "", "file"), "file").string();
  if (j.contains("time_utc")) r.time_utc = JsonString(j["time_utc"], "time_utc");
  r.settings = j.value("settings", Json::object());
  r.exif = j.value("exif", Json::object());
  if (j.contains("flags"))
    for (const Json& flag : JsonArray(j["flags"], "flags", 0, 64)) r.flags.push_back(JsonString(flag, "flags[]"));
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
  MESOCAP_RETURN_IF_ERROR(WriteJsonFile(s.layout().manifest(), s.manifest_));
  return s;
}

StatusOr<Session> Session::Open(const fs::path& root) {
  Session s;
  s.root_ = root;
  const fs::path manifest_path = s.layout().manifest();
  if (!fs::exists(manifest_path))
    return Status::Error(root.string() + ": not a mesocap session (no " + manifest_path.filename().string() + ")");
  auto manifest = ReadJsonFile(manifest_path);
  if (!manifest.ok()) return manifest.status();
  if (!manifest->is_object())
    return Status::Error(manifest_path.string() + ": must be a JSON object, not " + manifest->type_name());
  if (manifest->contains("format") && (*manifest)["format"] != "mesocap-session")
    return Status::Error(manifest_path.string() + ": format is " + (*manifest)["format"].dump() +
                         ", not \"mesocap-session\"");
  s.manifest_ = std::move(*manifest);
  const fs::path journal = s.layout().journal();
  if (fs::exists(journal)) {
    auto text = ReadTextFile(journal);
    if (!text.ok()) return text.status();
    std::istringstream lines(*text);
    std::string line;
    for (int number = 1; std::getline(lines, line); ++number) {
      if (line.empty()) continue;
      Json j;
      try {
        j = Json::parse(line);
      } catch (const std::exception&) {
        ++s.torn_lines_;  // a crash mid-append cuts at most the last line
        continue;
      }
      if (!j.is_object()) continue;
      const Json event = j.value("event", Json());
      try {
        if (event == "shot") {
          s.shots_.push_back(ShotRecord::FromJson(j));
        } else if (event == "reject") {
          const std::string file = JsonRelativePath(JsonField(j, "", "file"), "file").string();
          if (!s.Journaled(file)) throw JsonFieldError("rejects " + file + ", which no earlier line records");
          s.rejected_[file] = j.value("reason", "");
        }
      } catch (const std::exception& e) {
        return Status::Error(journal.string() + " line " + std::to_string(number) + ": " + e.what());
      }
    }
  }
  return s;
}

Status Session::UpdateManifest(const Json& patch) {
  Json updated = manifest_;
  updated.merge_patch(patch);
  MESOCAP_RETURN_IF_ERROR(WriteJsonFile(layout().manifest(), updated));
  manifest_ = std::move(updated);
  return Status::Ok();
}

Status Session::RecordShot(const ShotRecord& record) {
  Json j = record.ToJson();
  j["event"] = "shot";
  MESOCAP_RETURN_IF_ERROR(AppendLineDurably(layout().journal(), j.dump()));
  shots_.push_back(record);
  return Status::Ok();
}

Status Session::RejectShot(const std::string& file, const std::string& reason) {
  if (!Journaled(file)) return Status::Error(root_.string() + ": no shot " + file + " in the journal");
  if (IsRejected(file)) return Status::Error(root_.string() + ": " + file + " is rejected already");
  const Json j = {{"event", "reject"}, {"file", file}, {"time_utc", UtcNowIso8601()}, {"reason", reason}};
  MESOCAP_RETURN_IF_ERROR(AppendLineDurably(layout().journal(), j.dump()));
  rejected_[file] = reason;
  return Status::Ok();
}

bool Session::Journaled(const std::string& file) const {
  return std::any_of(shots_.begin(), shots_.end(), [&](const ShotRecord& r) { return r.file == file; });
}

std::vector<ShotRecord> Session::ShotsOfKind(const std::string& kind) const {
  std::vector<ShotRecord> out;
  std::copy_if(shots_.begin(), shots_.end(), std::back_inserter(out),
               [&](const ShotRecord& r) { return r.kind == kind && !IsRejected(r.file); });
  return out;
}

int Session::NextIndex(const std::string& kind) const {
  int highest = 0;
  for (const auto& r : shots_)
    if (r.kind == kind) highest = std::max(highest, r.index);
  // Files present but never journaled (a crash between rename and append) also block reuse.
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(layout().shots_of_kind(kind), ec))
    highest = std::max(highest, SessionLayout::ShotIndexOf(kind, entry.path().filename().string()));
  return highest + 1;
}

}  // namespace mesocap

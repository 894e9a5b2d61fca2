// A session folder: session.json (manifest, written atomically), journal.jsonl (one JSON object
// per completed shot, appended and fsynced; a later record may reject a shot), shots/ and calib/
// (originals, never modified nor deleted), and one folder per later stage. Layout and formats:
// docs/formats.md.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/json.h"
#include "core/session_layout.h"
#include "core/status.h"

namespace mesocap {

// Shot indices are 1-based and below this bound (file names hold 4 to 6 digits).
inline constexpr int kMaxShotIndex = 999999;

struct ShotRecord {
  int index = 0;              // 1-based, per kind, never reused
  std::string kind = "shot";  // "shot" (lit by the flash) or "calib" (checkerboard)
  std::string file;           // relative to the session root, e.g. "shots/shot_0001.jpg"
  std::string time_utc;
  Json settings = Json::object();  // camera settings when it was taken
  Json exif = Json::object();      // read back from the file
  std::vector<std::string> flags;  // e.g. "flash_not_fired"

  Json ToJson() const;
  // Throws JsonFieldError on a missing or out-of-range field, or a file path that is absolute or
  // leaves the session ("..").
  static ShotRecord FromJson(const Json& j);
};

class Session {
 public:
  // Creates a new session at `root`, which must not exist or be an empty folder.
  // `manifest` holds the caller's fields (source, camera, provenance ...).
  static StatusOr<Session> Create(const std::filesystem::path& root, Json manifest);
  // Opens an existing session and replays its journal; a torn last line (a crash while
  // appending) is ignored and counted.
  static StatusOr<Session> Open(const std::filesystem::path& root);

  const std::filesystem::path& root() const { return root_; }
  SessionLayout layout() const { return SessionLayout(root_); }
  const Json& manifest() const { return manifest_; }
  Status UpdateManifest(const Json& patch);  // merge_patch + atomic rewrite

  // Appends a completed shot to the journal. Call only after its file is in place.
  Status RecordShot(const ShotRecord& record);
  // Appends a record that takes the journaled shot `file` out of the session (an operator's
  // undo): its file stays, every stage leaves it out. An unknown or already rejected file is an error.
  Status RejectShot(const std::string& file, const std::string& reason);
  // Every journaled shot, rejected ones included (their files and indices stay taken).
  const std::vector<ShotRecord>& shots() const { return shots_; }
  // The shots of a kind the stages use: rejected ones left out.
  std::vector<ShotRecord> ShotsOfKind(const std::string& kind) const;
  bool IsRejected(const std::string& file) const { return rejected_.count(file) > 0; }
  const std::map<std::string, std::string>& rejected() const { return rejected_; }  // file -> reason
  // Next free index of a kind: one past the highest recorded, so resuming never overwrites.
  int NextIndex(const std::string& kind) const;
  int torn_journal_lines() const { return torn_lines_; }

 private:
  bool Journaled(const std::string& file) const;

  std::filesystem::path root_;
  Json manifest_;
  std::vector<ShotRecord> shots_;
  std::map<std::string, std::string> rejected_;
  int torn_lines_ = 0;
};

// True when `dir` does not exist or is an empty folder.
bool IsMissingOrEmptyDir(const std::filesystem::path& dir);

}  // namespace mesocap

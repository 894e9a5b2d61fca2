// `mesocap import`: builds a session from folders of photos taken elsewhere (JPEG, PNG, TIFF,
// camera RAW through OpenImageIO/libraw). Photos are ordered by EXIF capture time, with the file
// modification time as the fallback and the file name breaking ties. Every file that is not a
// fully decodable image (unreadable, not an image, empty, truncated) is listed in the report
// with the reason and skipped, never fatal. Originals are hard-linked or copied, never modified.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/json.h"
#include "core/progress.h"
#include "core/status.h"

namespace mesocap {

// How an original gets into the session. Either way the session's file has the original's bytes.
enum class LinkMode {
  kHardlink,  // hard link (no extra space); falls back to a copy when linking is impossible
              // (another file system, no permission, link limit)
  kCopy,      // always copy: temp file beside the final name, fsync, rename
};
std::string LinkModeToString(LinkMode mode);             // "hardlink", "copy"
bool StringToLinkMode(const std::string& s, LinkMode* mode);  // false when unknown

struct ImportOptions {
  std::filesystem::path photo_dir;        // flash shots; imported as kind "shot" into shots/
  std::filesystem::path calibration_dir;  // optional (empty: none); kind "calib" into calib/
  std::filesystem::path out;              // new session; must not exist or be an empty folder
  LinkMode link_mode = LinkMode::kHardlink;

  std::string Check() const;  // empty when valid, else a message for the user
  Json ToJson() const;
};

struct ImportedPhoto {
  std::filesystem::path source;  // the original, absolute
  std::string file;              // in the session, relative to its root ("shots/shot_0001.jpg")
  std::string kind;              // "shot" or "calib"
  int index = 0;
  std::string capture_time;  // ISO 8601 from `time_source`; "Z" only when UTC is known (EXIF
                             // with an offset, or file time), else the camera clock as written
  std::string time_source;       // "exif:DateTimeOriginal", "exif:DateTime", ... or "file_mtime"
  std::string method;            // "hardlink" or "copy"
  uintmax_t bytes = 0;
  Json ToJson() const;
};

struct SkippedFile {
  std::filesystem::path source;
  std::string reason;  // e.g. "empty file", "Premature end of JPEG file", "not an image ..."
  Json ToJson() const;
};

struct ImportReport {
  std::filesystem::path out;
  int shots_imported = 0, calib_shots_imported = 0;
  int hardlinked = 0, copied = 0;
  std::vector<ImportedPhoto> imported;  // in session order: calib first, then shots
  std::vector<SkippedFile> skipped;     // in folder-listing (name) order
  std::vector<std::string> warnings;    // e.g. capture times from mixed sources
  double total_s = 0, per_image_s = 0;

  int imported_count() const { return shots_imported + calib_shots_imported; }
  Json ToJson() const;  // written as SESSION/import_report.json
  std::string Brief() const;
};

// Imports `options.photo_dir` (and `calibration_dir`) into a new session at `options.out`.
// The session is assembled in a hidden staging folder beside `out` and renamed into place only
// when complete, so a failed or cancelled import leaves nothing that looks like a session.
// Errors: an invalid option (see Check), a folder with no importable photo, or I/O failure
// while writing the session. Progress: one step per file examined, then one per file placed.
StatusOr<ImportReport> ImportPhotoFolder(const ImportOptions& options, const ProgressFn& progress = nullptr);

}  // namespace mesocap

#include "capture/import.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>
#include <optional>

#include "capture/photo_metadata.h"
#include "core/atomic_file.h"
#include "core/image_io.h"
#include "core/progress.h"
#include "core/provenance.h"
#include "core/session.h"
#include "core/text_format.h"
#include "core/session_layout.h"

namespace mesocap {
namespace fs = std::filesystem;

namespace {

// Seconds since the epoch of an EXIF date-time "YYYY:MM:DD HH:MM:SS" (any single separators),
// plus its sub-second digits and "+HH:MM" UTC offset when known. Without an offset the camera's
// clock is read as if it were UTC: the order among such photos is the camera's order.
std::optional<double> ParseExifTime(const std::string& text, const std::string& subsec,
                                    const std::string& offset, bool* has_offset) {
  int y, mo, d, h, mi, s;
  if (std::sscanf(Trim(text).c_str(), "%4d%*1[:-]%2d%*1[:-]%2d%*1[ T]%2d:%2d:%2d", &y, &mo, &d, &h, &mi, &s) != 6)
    return std::nullopt;
  if (y < 1900 || y > 2200 || mo < 1 || mo > 12 || d < 1 || d > 31 || h > 23 || mi > 59 || s > 60)
    return std::nullopt;  // also rejects the "0000:00:00 00:00:00" some cameras write
  std::tm tm{};
  tm.tm_year = y - 1900;
  tm.tm_mon = mo - 1;
  tm.tm_mday = d;
  tm.tm_hour = h;
  tm.tm_min = mi;
  tm.tm_sec = s;
  double t = double(::timegm(&tm));
  const std::string digits = Trim(subsec);
  if (!digits.empty() && digits.size() <= 9 &&
      std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); }))
    t += std::stod(digits) / std::pow(10.0, double(digits.size()));
  int oh = 0, om = 0;
  char sign = 0;
  *has_offset = false;
  if (std::sscanf(Trim(offset).c_str(), "%c%2d:%2d", &sign, &oh, &om) == 3 && (sign == '+' || sign == '-') &&
      oh <= 14 && om < 60) {
    t -= (sign == '-' ? -1 : 1) * (oh * 3600.0 + om * 60.0);
    *has_offset = true;
  }
  return t;
}

std::string FormatTime(double epoch_s, bool utc_known) {
  const std::time_t whole = std::time_t(std::floor(epoch_s));
  std::tm tm{};
  ::gmtime_r(&whole, &tm);
  char buf[48];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", &tm);
  std::string out = buf;
  const int ms = int(std::lround((epoch_s - double(whole)) * 1000.0));
  if (ms > 0 && ms < 1000) {
    char frac[8];
    std::snprintf(frac, sizeof frac, ".%03d", ms);
    out += frac;
  }
  return utc_known ? out + "Z" : out;  // no "Z": camera clock, time zone unknown
}

struct CaptureTime {
  double epoch_s = 0;
  std::string source;  // "exif:DateTimeOriginal" ... or "file_mtime"
  bool utc_known = false;
};

CaptureTime CaptureTimeOf(const ImageAttributes& attrs, const fs::path& file) {
  struct Field {
    const char *time, *subsec, *offset, *label;
  };
  static const Field kFields[] = {
      {"Exif:DateTimeOriginal", "Exif:SubsecTimeOriginal", "Exif:OffsetTimeOriginal", "exif:DateTimeOriginal"},
      {"Exif:DateTimeDigitized", "Exif:SubsecTimeDigitized", "Exif:OffsetTimeDigitized", "exif:DateTimeDigitized"},
      {"DateTime", "Exif:SubsecTime", "Exif:OffsetTime", "exif:DateTime"},
  };
  for (const Field& f : kFields) {
    const std::string* text = StringAttr(attrs, f.time);
    if (!text) continue;
    const std::string* subsec = StringAttr(attrs, f.subsec);
    const std::string* offset = StringAttr(attrs, f.offset);
    bool has_offset = false;
    if (auto t = ParseExifTime(*text, subsec ? *subsec : "", offset ? *offset : "", &has_offset))
      return {*t, f.label, has_offset};
  }
  std::error_code ec;
  const auto ft = fs::last_write_time(file, ec);
  CaptureTime ct;
  ct.source = "file_mtime";
  ct.utc_known = true;
  if (!ec) {
    const auto sys = std::chrono::file_clock::to_sys(ft);
    ct.epoch_s = std::chrono::duration<double>(sys.time_since_epoch()).count();
  }
  return ct;
}

// Extension in the session: the usual one for JPEG/PNG/TIFF, else the original's (RAW readers
// go by it), lower-cased.
std::string SessionExtension(const ImageInfo& info, const fs::path& source) {
  if (info.format_name == "jpeg") return ".jpg";
  if (info.format_name == "png") return ".png";
  if (info.format_name == "tiff") return ".tif";
  if (info.format_name == "openexr") return ".exr";
  std::string ext = Lower(source.extension().string());
  return ext.empty() ? "." + info.format_name : ext;
}

// The error text without the leading "path: " every core error carries.
std::string ReasonOf(const Status& st, const fs::path& path) {
  std::string msg = st.message();
  const std::string prefix = path.string() + ": ";
  if (msg.rfind(prefix, 0) == 0) msg = msg.substr(prefix.size());
  if (msg.find("could not find a format reader") != std::string::npos)
    return "not an image file (no image reader recognises it)";
  // Readers quote the full path inside their messages; the report lists the file already.
  for (size_t at; (at = msg.find(path.string())) != std::string::npos;)
    msg.replace(at, path.string().size(), path.filename().string());
  msg = Trim(msg);
  return msg.empty() ? "not a readable image" : msg;
}

struct Candidate {
  fs::path source;  // absolute, symlinks resolved
  std::string kind;
  ImageInfo info;
  CaptureTime time;
};

// The entries of `dir`, sorted by name.
Status ListFolder(const fs::path& dir, std::vector<fs::directory_entry>* entries) {
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) entries->push_back(*it);
  if (ec) return Status::Error(dir.string() + ": cannot list folder: " + ec.message());
  std::sort(entries->begin(), entries->end(),
            [](const auto& a, const auto& b) { return a.path().filename() < b.path().filename(); });
  return Status::Ok();
}

// Examines `entries` in order: decodable images become candidates, everything else is listed in
// `skipped` with the reason (and drops out of the progress total).
Status ScanEntries(const std::vector<fs::directory_entry>& entries, const std::string& kind,
                   const ProgressFn& progress, int* done, int* total, std::vector<Candidate>* candidates,
                   std::vector<SkippedFile>* skipped) {
  for (const auto& entry : entries) {
    const fs::path path = entry.path();
    if (!ReportProgress(progress, ++*done, *total, path.filename().string()))
      return Status::Cancelled();
    std::error_code e;
    if (entry.is_directory(e)) {
      skipped->push_back({fs::absolute(path), "folder (import does not look inside sub-folders)"});
      --*total;
      continue;
    }
    if (!entry.is_regular_file(e)) {
      skipped->push_back({fs::absolute(path), entry.is_symlink(e) ? "broken symbolic link" : "not a regular file"});
      --*total;
      continue;
    }
    const fs::path source = fs::canonical(path, e);  // link the file itself, not a symlink to it
    if (e) {
      skipped->push_back({fs::absolute(path), "cannot resolve path: " + e.message()});
      --*total;
      continue;
    }
    // A full decode, not just the header: OpenImageIO opens a truncated JPEG happily and only
    // the pixel read reports it.
    ImageReadOptions read_options;
    read_options.linearize = false;
    ImageInfo info;
    auto image = ReadImage(source, read_options, &info);
    if (!image.ok()) {
      skipped->push_back({fs::absolute(path), ReasonOf(image.status(), source)});
      --*total;
      continue;
    }
    candidates->push_back({source, kind, std::move(info), {}});
    candidates->back().time = CaptureTimeOf(candidates->back().info.attributes, source);
  }
  return Status::Ok();
}

// Puts `source` at `dest` by hard link or atomic copy; returns the method used.
StatusOr<std::string> PlaceOriginal(const fs::path& source, const fs::path& dest, LinkMode mode) {
  std::error_code ec;
  if (mode == LinkMode::kHardlink) {
    fs::create_hard_link(source, dest, ec);  // link(2) is atomic: the name appears whole or not
    if (!ec) return std::string("hardlink");
    fs::remove(dest, ec);  // never there on failure, but be certain before copying
  }
  Status st = WriteFileAtomically(dest, [&](const fs::path& temp) -> Status {
    std::error_code e;
    fs::copy_file(source, temp, fs::copy_options::none, e);
    if (e) return Status::Error(source.string() + ": cannot copy to " + dest.string() + ": " + e.message());
    const auto mtime = fs::last_write_time(source, e);  // keep the original's file time
    if (!e) fs::last_write_time(temp, mtime, e);
    return Status::Ok();
  });
  if (!st.ok()) return st;
  return std::string("copy");
}

}  // namespace

std::string LinkModeToString(LinkMode mode) { return mode == LinkMode::kCopy ? "copy" : "hardlink"; }

bool StringToLinkMode(const std::string& s, LinkMode* mode) {
  if (s == "hardlink") *mode = LinkMode::kHardlink;
  else if (s == "copy") *mode = LinkMode::kCopy;
  else return false;
  return true;
}

std::string ImportOptions::Check() const {
  std::error_code ec;
  if (photo_dir.empty()) return "a photo folder is required";
  if (!fs::exists(photo_dir, ec)) return photo_dir.string() + ": no such folder";
  if (!fs::is_directory(photo_dir, ec)) return photo_dir.string() + ": not a folder";
  if (!calibration_dir.empty()) {
    if (!fs::exists(calibration_dir, ec)) return calibration_dir.string() + ": no such folder (--calibration-dir)";
    if (!fs::is_directory(calibration_dir, ec)) return calibration_dir.string() + ": not a folder (--calibration-dir)";
    if (fs::equivalent(photo_dir, calibration_dir, ec))
      return "--calibration-dir must differ from the photo folder " + photo_dir.string();
  }
  if (out.empty()) return "--out is required";
  if (!IsMissingOrEmptyDir(out)) return out.string() + ": exists and is not empty; choose a new folder";
  if (fs::exists(out, ec) && fs::equivalent(out, photo_dir, ec)) return "--out must differ from the photo folder";
  return "";
}

Json ImportOptions::ToJson() const {
  return {{"photo_dir", fs::absolute(photo_dir).lexically_normal().string()},
          {"calibration_dir", calibration_dir.empty() ? "" : fs::absolute(calibration_dir).lexically_normal().string()},
          {"out", fs::absolute(out).lexically_normal().string()},
          {"link_mode", LinkModeToString(link_mode)}};
}

Json ImportedPhoto::ToJson() const {
  return {{"source", source.string()}, {"file", file}, {"kind", kind}, {"index", index},
          {"capture_time", capture_time}, {"time_source", time_source}, {"method", method},
          {"bytes", bytes}};
}

Json SkippedFile::ToJson() const { return {{"source", source.string()}, {"reason", reason}}; }

Json ImportReport::ToJson() const {
  Json imported_json = Json::array(), skipped_json = Json::array();
  for (const auto& p : imported) imported_json.push_back(p.ToJson());
  for (const auto& s : skipped) skipped_json.push_back(s.ToJson());
  return {{"out", out.string()},
          {"imported_count", imported_count()},
          {"shots_imported", shots_imported},
          {"calib_shots_imported", calib_shots_imported},
          {"skipped_count", int(skipped.size())},
          {"hardlinked", hardlinked},
          {"copied", copied},
          {"total_s", total_s},
          {"per_image_s", per_image_s},
          {"warnings", warnings},
          {"imported", imported_json},
          {"skipped", skipped_json}};
}

std::string ImportReport::Brief() const {
  char buf[512];
  std::snprintf(buf, sizeof buf, "imported %d shots + %d calibration shots (%d hard-linked, %d copied), skipped %d "
                "files, in %.1f s -> %s", shots_imported, calib_shots_imported, hardlinked, copied,
                int(skipped.size()), total_s, out.string().c_str());
  // import_report.json lists them all.
  std::string text = buf + ListedLines(skipped, 20, SessionLayout(out).import_report().filename().string(), [](const SkippedFile& f) {
                       return "skipped " + f.source.filename().string() + ": " + f.reason;
                     });
  for (const auto& w : warnings) text += "\n  warning: " + w;
  return text;
}

StatusOr<ImportReport> ImportPhotoFolder(const ImportOptions& options, const ProgressFn& progress) {
  if (std::string why = options.Check(); !why.empty()) return Status::Error(why);
  const auto t0 = std::chrono::steady_clock::now();
  ImportReport report;

  // 1. Examine every file: calibration shots first (the session order), each folder by name.
  std::vector<fs::directory_entry> calib_entries, shot_entries;
  if (!options.calibration_dir.empty()) MESOCAP_RETURN_IF_ERROR(ListFolder(options.calibration_dir, &calib_entries));
  MESOCAP_RETURN_IF_ERROR(ListFolder(options.photo_dir, &shot_entries));
  std::vector<Candidate> calib, shots;
  int done = 0, total = 2 * int(calib_entries.size() + shot_entries.size());  // examine + place
  MESOCAP_RETURN_IF_ERROR(ScanEntries(calib_entries, "calib", progress, &done, &total, &calib, &report.skipped));
  MESOCAP_RETURN_IF_ERROR(ScanEntries(shot_entries, "shot", progress, &done, &total, &shots, &report.skipped));
  if (shots.empty()) {
    std::string why = options.photo_dir.string() + ": no importable photo (JPEG, PNG, TIFF or camera RAW)";
    if (!report.skipped.empty())
      why += "; skipped " + std::to_string(report.skipped.size()) + " files, first " +
             report.skipped.front().source.filename().string() + ": " + report.skipped.front().reason;
    return Status::Error(why);
  }

  // 2. Order each kind by capture time, then name.
  for (auto* list : {&calib, &shots}) {
    std::stable_sort(list->begin(), list->end(), [](const Candidate& a, const Candidate& b) {
      if (a.time.epoch_s != b.time.epoch_s) return a.time.epoch_s < b.time.epoch_s;
      return a.source.filename() < b.source.filename();
    });
    int from_exif = 0, naive_exif = 0;
    std::map<std::string, std::vector<std::string>> by_stem;
    for (const auto& c : *list) {
      if (c.time.source != "file_mtime") ++from_exif;
      if (c.time.source != "file_mtime" && !c.time.utc_known) ++naive_exif;
      by_stem[Lower(c.source.stem().string())].push_back(c.source.filename().string());
    }
    const std::string what = list == &calib ? "calibration shots" : "shots";
    const int n = int(list->size());
    if (from_exif > 0 && from_exif < n)
      report.warnings.push_back(what + ": " + std::to_string(n - from_exif) + " of " + std::to_string(n) +
                                " have no EXIF capture time and are ordered by file time" +
                                (naive_exif ? " (the camera clock's time zone is unknown, so their order against "
                                              "EXIF-timed photos may be off by its UTC offset)"
                                            : ""));
    for (const auto& [stem, names] : by_stem) {
      if (names.size() < 2) continue;
      std::string joined;
      for (const auto& nm : names) joined += (joined.empty() ? "" : ", ") + nm;
      report.warnings.push_back(what + ": " + joined + " share a name and are imported as separate shots "
                                "(a RAW+JPEG pair? keep one of them and import again)");
    }
  }

  // 3. Assemble the session in a staging folder.
  fs::path out_clean = fs::absolute(options.out).lexically_normal();
  if (out_clean.filename().empty()) out_clean = out_clean.parent_path();  // "dir/" -> "dir"
  // Any early return or exception removes the staging folder (StagingFolder's destructor).
  auto staged = StagingFolder::Begin(out_clean);
  if (!staged.ok()) return staged.status();
  const fs::path staging = staged->path();
  std::error_code ec;

  Json camera = {{"model", "unknown"}, {"port", "import"}};
  {
    const Json exif = ExifOf(shots.front().info);
    const std::string model = Trim(exif.value("Make", "") + " " + exif.value("Model", ""));
    if (!model.empty()) camera["model"] = model;
  }
  Json manifest = {{"source", "import"}, {"camera", camera}, {"provenance", MakeProvenance(options.ToJson())}};
  auto session = Session::Create(staging, manifest);
  if (!session.ok()) return session.status();
  const SessionLayout layout(staging);
  fs::create_directories(layout.shots(), ec);
  if (!ec) fs::create_directories(layout.calib(), ec);
  if (ec) return Status::Error(staging.string() + ": cannot create folders: " + ec.message());

  total = done + int(calib.size() + shots.size());
  const auto t_place = std::chrono::steady_clock::now();
  for (auto* list : {&calib, &shots}) {
    int index = 0;
    for (const Candidate& c : *list) {
      ++index;
      const std::string file = SessionLayout::ShotEntry(c.kind, index, SessionExtension(c.info, c.source));
      const fs::path dest = staging / file;
      auto method = PlaceOriginal(c.source, dest, options.link_mode);
      if (!method.ok()) return method.status();
      std::error_code e_source, e_dest;
      const uintmax_t source_bytes = fs::file_size(c.source, e_source), dest_bytes = fs::file_size(dest, e_dest);
      if (e_source || e_dest || source_bytes != dest_bytes)
        return Status::Error(dest.string() + ": size differs from the original " + c.source.string() +
                             " after " + *method + " (was it changed while importing?)");

      ShotRecord record;
      record.index = index;
      record.kind = c.kind;
      record.file = file;
      record.time_utc = FormatTime(c.time.epoch_s, c.time.utc_known);
      record.settings = {{"imported_from", c.source.string()}};
      record.exif = ExifOf(c.info);
      if (c.time.source == "file_mtime") record.flags.push_back("time_from_file_mtime");
      if (c.kind == "shot" && record.exif.contains("Flash") && (record.exif["Flash"].get<int>() & 1) == 0)
        record.flags.push_back("flash_not_fired");
      if (Status st = session->RecordShot(record); !st.ok()) return st;

      ImportedPhoto photo;
      photo.source = c.source;
      photo.file = file;
      photo.kind = c.kind;
      photo.index = index;
      photo.capture_time = record.time_utc;
      photo.time_source = c.time.source;
      photo.method = *method;
      photo.bytes = dest_bytes;
      report.imported.push_back(photo);
      (*method == "hardlink" ? report.hardlinked : report.copied)++;
      (c.kind == "calib" ? report.calib_shots_imported : report.shots_imported)++;
      if (!ReportProgress(progress, ++done, total, file)) return Status::Cancelled();
    }
  }
  // Hard links are new folder entries: make them durable before the session appears.
  for (const fs::path& dir : {layout.shots(), layout.calib()})
    if (Status st = SyncPath(dir); !st.ok()) return st;

  report.out = out_clean;
  report.per_image_s = SecondsSince(t_place) / std::max(1, report.imported_count());
  report.total_s = SecondsSince(t0);
  if (Status st = WriteJsonFile(layout.import_report(), report.ToJson()); !st.ok()) return st;

  // Only now does the session appear under its name.
  if (Status st = staged->Publish(); !st.ok()) return st;
  return report;
}

}  // namespace mesocap

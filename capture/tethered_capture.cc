#include "capture/tethered_capture.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <optional>
#include <set>
#include <thread>

#include "capture/photo_metadata.h"
#include "core/atomic_file.h"
#include "core/image_io.h"
#include "core/progress.h"
#include "core/provenance.h"
#include "core/session.h"
#include "core/session_lock.h"
#include "core/text_format.h"
#include "core/session_layout.h"

namespace mesocap {
namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

void SleepSeconds(double s) {
  if (s > 0) std::this_thread::sleep_for(std::chrono::duration<double>(s));
}

bool SplitSetting(const std::string& setting, std::string* key, std::string* value) {
  const size_t eq = setting.find('=');
  if (eq == std::string::npos) return false;
  *key = Trim(setting.substr(0, eq));
  *value = Trim(setting.substr(eq + 1));
  return !key->empty();
}

// The same EXIF fields, under the same names, as `mesocap import` journals (capture/import.cc).
// Extension in the session from the name on the card: lower case, ".jpeg" -> ".jpg".
std::string ExtensionFor(const std::string& name_on_card) {
  std::string ext = Lower(fs::path(name_on_card).extension().string());
  if (ext == ".jpeg") ext = ".jpg";
  return ext.empty() ? ".bin" : ext;
}

// A JPEG that was cut short has no end-of-image marker near its end (entropy-coded data
// stuffs every 0xFF, so FF D9 there is the real marker; some bodies pad after it).
bool JpegLooksComplete(const fs::path& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return false;
  const std::streamoff size = in.tellg();
  if (size < 4) return false;
  const std::streamoff tail = std::min<std::streamoff>(size, 1024);
  std::string buf(size_t(tail), '\0');
  in.seekg(size - tail);
  in.read(buf.data(), tail);
  for (size_t i = buf.size() - 1; i > 0; --i)
    if (uint8_t(buf[i - 1]) == 0xFF && uint8_t(buf[i]) == 0xD9) return true;
  return false;
}

std::string StopReasonFor(CameraError error) {
  switch (error) {
    case CameraError::kGone: return "camera_gone";
    case CameraError::kCardFull: return "card_full";
    case CameraError::kDiskFull: return "disk_full";
    case CameraError::kBusy:
    case CameraError::kIo: return "camera_not_responding";
    default: return "error";
  }
}

// Runs `op` until it succeeds or fails for a reason retrying cannot fix.
CameraStatus WithRetry(const RetryOptions& retry, int* retries, const std::function<CameraStatus()>& op) {
  double backoff = retry.initial_backoff_s;
  CameraStatus st;
  for (int attempt = 1;; ++attempt) {
    st = op();
    if (st.ok() || !st.retryable()) return st;
    if (attempt >= retry.max_attempts) break;
    ++*retries;
    SleepSeconds(backoff);
    backoff = std::min(retry.max_backoff_s, backoff * 2);
  }
  st.message += " (gave up after " + std::to_string(retry.max_attempts) + " attempts)";
  return st;
}

// Settings worth recording with every shot when the body has them, besides those --set.
const char* const kRecordedSettings[] = {"iso", "shutterspeed", "f-number", "aperture", "exposurecompensation",
                                         "imageformat", "imagequality", "imagesize", "capturetarget",
                                         "flashmode", "focallength", "whitebalance", "exposureprogram"};

std::string SettingsSummary(const Json& settings) {
  std::string s;
  for (const char* key : {"f-number", "aperture", "shutterspeed", "iso"})
    if (settings.contains(key)) s += (s.empty() ? "" : " ") + std::string(key == std::string("iso") ? "ISO " : "") +
                                     settings[key].get<std::string>();
  return s;
}

std::string FileTimeUtc(const fs::path& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 ? UtcIso8601(st.st_mtime) : "";
}

ShotRecord RecordFor(int index, const std::string& kind, const std::string& file, const fs::path& path) {
  ShotRecord record;
  record.index = index;
  record.kind = kind;
  record.file = file;
  auto info = ReadImageInfo(path);
  if (info.ok()) {
    record.exif = ExifOf(*info);
    if (kind == "shot" && record.exif.contains("Flash") && (record.exif["Flash"].get<int>() & 1) == 0)
      record.flags.push_back("flash_not_fired");
  } else {
    record.flags.push_back("exif_unreadable");
  }
  return record;
}

// A crash while appending can leave the journal's last line without its newline; the next
// append would then be glued onto that torn line and lost with it. Ends the torn line first.
Status TerminateTornJournalLine(const fs::path& journal) {
  std::ifstream in(journal, std::ios::binary | std::ios::ate);
  if (!in) return Status::Ok();  // no journal yet
  const std::streamoff size = in.tellg();
  if (size <= 0) return Status::Ok();
  in.seekg(size - 1);
  char last = '\n';
  in.get(last);
  if (last == '\n') return Status::Ok();
  return AppendLineDurably(journal, "");  // readers skip the empty remainder
}

// On resume: deletes temp files of interrupted downloads and journals complete files that a
// crash left between their rename and their journal line.
Status TidyAfterCrash(Session* session, const std::string& kind, CaptureReport* report) {
  const fs::path dir = session->layout().shots_of_kind(kind);
  std::error_code ec;
  if (!fs::exists(dir, ec)) return Status::Ok();
  std::set<std::string> journaled;
  for (const auto& r : session->shots()) journaled.insert(fs::path(r.file).filename().string());
  std::vector<fs::path> orphans;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.rfind("." + kind + "_", 0) == 0 && name.find(".tmp") != std::string::npos) {
      std::error_code e;
      if (fs::remove(it->path(), e)) ++report->removed_partial_files;
      continue;
    }
    if (SessionLayout::ShotIndexOf(kind, name) > 0 && !journaled.count(name)) orphans.push_back(it->path());
  }
  if (ec) return Status::Error(dir.string() + ": cannot list folder: " + ec.message());
  std::sort(orphans.begin(), orphans.end());
  for (const fs::path& path : orphans) {
    const int n = SessionLayout::ShotIndexOf(kind, path.filename().string());
    const std::string file = session->layout().Relative(path);
    ShotRecord record = RecordFor(n, kind, file, path);
    record.time_utc = FileTimeUtc(path);
    record.flags.push_back("recovered");
    MESOCAP_RETURN_IF_ERROR(session->RecordShot(record));
    ++report->recovered;
    report->warnings.push_back(file + ": complete but unjournaled after an interruption; journaled now (flag "
                               "\"recovered\", settings unknown)");
  }
  return Status::Ok();
}

}  // namespace

std::string CaptureModeToString(CaptureMode mode) {
  switch (mode) {
    case CaptureMode::kInterval: return "interval";
    case CaptureMode::kEnter: return "enter";
    case CaptureMode::kRemote: return "remote";
  }
  return "interval";
}

bool StringToCaptureMode(const std::string& s, CaptureMode* mode) {
  if (s == "interval") *mode = CaptureMode::kInterval;
  else if (s == "enter") *mode = CaptureMode::kEnter;
  else if (s == "remote") *mode = CaptureMode::kRemote;
  else return false;
  return true;
}

std::string CaptureOptions::Check() const {
  if (out.empty()) return "--out is required";
  if (mode == CaptureMode::kRemote ? shots < 0 : shots < 1)
    return mode == CaptureMode::kRemote ? "--shots must be >= 0 (0: until stopped)" : "--shots must be >= 1";
  if (!(interval_s >= 0) || !std::isfinite(interval_s)) return "--interval must be >= 0 seconds";
  if (!(remote_idle_timeout_s >= 0)) return "the remote idle timeout must be >= 0 seconds";
  if (retry.max_attempts < 1 || !(retry.initial_backoff_s >= 0) || !(retry.max_backoff_s >= 0))
    return "retry options must be positive";
  for (const auto& s : settings) {
    std::string key, value;
    if (!SplitSetting(s, &key, &value)) return "--set expects key=value, not '" + s + "'";
  }
  std::error_code ec;
  if (resume) {
    if (const fs::path manifest = SessionLayout(out).manifest(); !fs::exists(manifest, ec))
      return out.string() + ": not a mesocap session to resume (no " + manifest.filename().string() + ")";
  } else if (!IsMissingOrEmptyDir(out)) {
    return out.string() + ": exists and is not empty; choose a new folder or add --resume";
  }
  return "";
}

Json CaptureOptions::ToJson() const {
  return {{"out", fs::absolute(out).lexically_normal().string()},
          {"shots", shots},
          {"interval_s", interval_s},
          {"settings", settings},
          {"calibration", calibration},
          {"resume", resume},
          {"mode", CaptureModeToString(mode)},
          {"remote_idle_timeout_s", remote_idle_timeout_s},
          {"delete_from_camera", delete_from_camera},
          {"retry", {{"max_attempts", retry.max_attempts}, {"initial_backoff_s", retry.initial_backoff_s},
                     {"max_backoff_s", retry.max_backoff_s}}}};
}

Json CapturedShot::ToJson() const {
  return {{"index", index}, {"kind", kind}, {"file", file}, {"on_card", on_card}, {"bytes", bytes},
          {"camera_s", camera_s}, {"overhead_s", overhead_s}, {"retries", retries}, {"flags", flags}};
}

Json CaptureReport::ToJson() const {
  Json shots_json = Json::array();
  for (const auto& s : shots) shots_json.push_back(s.ToJson());
  return {{"out", out.string()},
          {"camera", {{"model", camera.model}, {"port", camera.port}}},
          {"settings", settings},
          {"first_index", first_index},
          {"shots_captured", shots_captured},
          {"recovered", recovered},
          {"removed_partial_files", removed_partial_files},
          {"retries", retries},
          {"flash_not_fired", flash_not_fired},
          {"stop_reason", stop_reason},
          {"error", error},
          {"warnings", warnings},
          {"total_s", total_s},
          {"mean_camera_s", mean_camera_s},
          {"mean_overhead_s", mean_overhead_s},
          {"max_overhead_s", max_overhead_s},
          {"shots", shots_json}};
}

std::string CaptureReport::Brief() const {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "captured %d shots (%s) from %s in %.1f s -> %s; camera %.1f ms/shot, mesocap overhead %.1f ms/shot "
                "(max %.1f ms), %d retries",
                shots_captured, stop_reason.c_str(), camera.model.c_str(), total_s, out.string().c_str(),
                mean_camera_s * 1e3, mean_overhead_s * 1e3, max_overhead_s * 1e3, retries);
  std::string text = buf;
  if (flash_not_fired) text += "\n  " + std::to_string(flash_not_fired) + " shots flagged flash_not_fired (kept)";
  if (recovered) text += "\n  journaled " + std::to_string(recovered) + " complete unjournaled files from an interrupted run";
  for (const auto& w : warnings) text += "\n  warning: " + w;
  return text;  // `error` is the caller's to print (one line on stderr)
}

Json CaptureManifest(const CameraInfo& camera, const CaptureOptions& options) {
  return {{"source", camera.port.rfind("fake:", 0) == 0 ? "fake" : "gphoto2"},
          {"camera", {{"model", camera.model}, {"port", camera.port}}},
          {"provenance", MakeProvenance(options.ToJson())}};
}

CameraStatus ValidateSettings(Camera& camera, const std::vector<std::string>& settings) {
  for (const auto& s : settings) {
    std::string key, value;
    if (!SplitSetting(s, &key, &value))
      return CameraStatus::Error(CameraError::kBadSetting, "--set expects key=value, not '" + s + "'");
    ConfigEntry entry;
    if (auto st = camera.GetConfig(key, &entry); !st.ok()) return st;
    if (entry.read_only)
      return CameraStatus::Error(CameraError::kBadSetting, camera.info().model + ": setting '" + key + "' is read-only");
    if (entry.type == "radio" || entry.type == "menu") {
      const bool valid = std::any_of(entry.choices.begin(), entry.choices.end(),
                                     [&](const std::string& c) { return Lower(c) == Lower(value); });
      if (!valid) {
        std::string choices;
        for (const auto& c : entry.choices) choices += (choices.empty() ? "" : ", ") + c;
        return CameraStatus::Error(CameraError::kBadSetting, camera.info().model + ": setting '" + key + "': '" +
                                                                 value + "' is not a valid value; choices: " + choices);
      }
    }
  }
  return CameraStatus::Ok();
}

StatusOr<CaptureReport> RunCapture(Camera& camera, const CaptureOptions& options, const ProgressFn& progress,
                                   const ReadyFn& ready, const AfterShotFn& after_shot) {
  if (std::string why = options.Check(); !why.empty()) return Status::Error(why);
  if (options.mode == CaptureMode::kEnter && !ready)
    return Status::Error("enter mode needs a way to wait for the photographer (no ReadyFn given)");
  const auto t_start = Clock::now();
  CaptureReport report;
  report.camera = camera.info();
  const std::string kind = options.calibration ? "calib" : "shot";

  // 1. Settings first: a rejected one stops before the session is touched.
  for (const auto& s : options.settings) {
    std::string key, value;
    SplitSetting(s, &key, &value);
    CameraStatus st = WithRetry(options.retry, &report.retries, [&] { return camera.SetConfig(key, value); });
    if (!st.ok()) return Status::Error(st.message);
  }
  std::vector<ConfigEntry> config;
  if (auto st = WithRetry(options.retry, &report.retries, [&] { return camera.ListConfig(&config); }); !st.ok())
    return Status::Error(st.message);
  {
    std::set<std::string> wanted(std::begin(kRecordedSettings), std::end(kRecordedSettings));
    for (const auto& s : options.settings) {
      std::string key, value;
      SplitSetting(s, &key, &value);
      wanted.insert(key);
    }
    for (const auto& e : config)
      if (wanted.count(e.name)) report.settings[e.name] = e.value;
  }

  // 2. The session: new, or reopened to resume.
  std::optional<Session> session;
  const fs::path root = fs::absolute(options.out).lexically_normal();
  report.out = root;
  // One writer per session (core/session_lock.h): a second capture into it would pick the same
  // indices. Taken before a resumed session's journal is read; released when the run ends.
  std::optional<SessionLock> lock;
  const auto acquire = [&lock, &root, &options]() -> Status {
    if (options.locked_by_caller) return Status::Ok();
    auto taken = SessionLock::Acquire(root, "capture");
    if (!taken.ok()) return taken.status();
    lock.emplace(std::move(*taken));
    return Status::Ok();
  };
  if (options.resume) {
    MESOCAP_RETURN_IF_ERROR(acquire());
    auto opened = Session::Open(root);
    if (!opened.ok()) return opened.status();
    session.emplace(std::move(*opened));
    if (session->torn_journal_lines())
      report.warnings.push_back(std::to_string(session->torn_journal_lines()) +
                                " torn journal line(s) from an interrupted run were ignored");
    const Json cam = session->manifest().value("camera", Json::object());
    if (cam.value("model", report.camera.model) != report.camera.model)
      report.warnings.push_back("the session was started with camera '" + cam.value("model", "") + "', now '" +
                                report.camera.model + "'");
  } else {
    auto created = Session::Create(root, CaptureManifest(report.camera, options));
    if (!created.ok()) return created.status();
    session.emplace(std::move(*created));
    MESOCAP_RETURN_IF_ERROR(acquire());
  }
  const fs::path dir = session->layout().shots_of_kind(kind);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return Status::Error(dir.string() + ": cannot create folder: " + ec.message());
  if (options.resume) {
    if (Status st = TerminateTornJournalLine(SessionLayout(root).journal()); !st.ok()) return st;
    if (Status st = TidyAfterCrash(&*session, kind, &report); !st.ok()) return st;
  }
  int next_index = session->NextIndex(kind);
  if (next_index - 1 + std::max(options.shots, 1) > kMaxShotIndex)
    return Status::Error(root.string() + ": no room for " + std::to_string(std::max(options.shots, 1)) + " more " + kind +
                         " files after index " + std::to_string(next_index - 1) + " (at most " +
                         std::to_string(kMaxShotIndex) + ")");
  report.first_index = next_index;

  // 3. One shot: place the file from the card, journal it.
  std::set<std::string> downloaded;  // on-card paths, so a repeated event is not a second shot
  auto finish = [&](const std::string& reason, const std::string& error) {
    report.stop_reason = reason;
    report.error = error;
  };
  // Returns false when the run must stop (report.error set).
  auto take = [&](const CameraFilePath& on_card, Clock::time_point t0, double camera_s_so_far,
                  int retries_so_far) -> bool {
    const std::string time_utc = UtcNowIso8601();
    const int index = next_index;
    if (index > kMaxShotIndex) {
      finish("session_full", "no shot index left after " + std::to_string(kMaxShotIndex));
      return false;
    }
    const std::string file = SessionLayout::ShotEntry(kind, index, ExtensionFor(on_card.name));
    const fs::path dest = root / file;
    double camera_s = camera_s_so_far;
    int retries = retries_so_far;
    int64_t bytes = 0;
    CameraStatus download_status;
    Status placed = WriteFileAtomically(dest, [&](const fs::path& temp) -> Status {
      const auto t_dl = Clock::now();  // retry pauses count as the camera's time, not mesocap's
      download_status = WithRetry(options.retry, &retries, [&]() -> CameraStatus {
        int64_t expected = -1;
        CameraStatus st = camera.Download(on_card, temp, &bytes, &expected);
        if (!st.ok()) return st;
        if (expected >= 0 && bytes != expected)
          return CameraStatus::Error(CameraError::kIo, on_card.ToString() + ": download incomplete: " +
                                                           std::to_string(bytes) + " of " + std::to_string(expected) +
                                                           " bytes");
        if (bytes == 0) return CameraStatus::Error(CameraError::kIo, on_card.ToString() + ": downloaded an empty file");
        if (ExtensionFor(on_card.name) == ".jpg" && !JpegLooksComplete(temp))
          return CameraStatus::Error(CameraError::kIo, on_card.ToString() + ": downloaded JPEG is damaged (no end "
                                                                            "marker)");
        return CameraStatus::Ok();
      });
      camera_s += SecondsSince(t_dl);
      return download_status.ToStatus();
    });
    report.retries += retries;
    if (!placed.ok()) {
      // Downloaded fine but the fsync or rename failed: the computer's disk, not the camera.
      const bool no_space = placed.message().find("No space left") != std::string::npos;
      finish(!download_status.ok() ? StopReasonFor(download_status.error) : no_space ? "disk_full" : "error",
             placed.message());
      return false;
    }
    ShotRecord record = RecordFor(index, kind, file, dest);
    record.time_utc = time_utc;
    record.settings = report.settings;
    record.settings["camera_file"] = on_card.ToString();
    if (Status st = session->RecordShot(record); !st.ok()) {
      finish("error", st.message());
      return false;
    }
    downloaded.insert(on_card.ToString());
    if (options.delete_from_camera) {  // only now: the session holds the file durably
      int delete_retries = 0;
      const auto t_del = Clock::now();
      CameraStatus del = WithRetry(options.retry, &delete_retries, [&] { return camera.DeleteFile(on_card); });
      camera_s += SecondsSince(t_del);
      retries += delete_retries;
      report.retries += delete_retries;
      if (!del.ok()) report.warnings.push_back("could not delete " + on_card.ToString() + " from the camera: " +
                                               del.message);
    }
    ++next_index;
    ++report.shots_captured;
    if (std::find(record.flags.begin(), record.flags.end(), "flash_not_fired") != record.flags.end())
      ++report.flash_not_fired;
    CapturedShot shot;
    shot.index = index;
    shot.kind = kind;
    shot.file = file;
    shot.on_card = on_card.ToString();
    shot.bytes = bytes;
    shot.camera_s = camera_s;
    shot.overhead_s = std::max(0.0, SecondsSince(t0) - camera_s);
    shot.retries = retries;
    shot.flags = record.flags;
    report.shots.push_back(shot);
    if (after_shot) after_shot(shot);
    return true;
  };

  // 4. The loop.
  const int total = options.shots;
  if (options.mode == CaptureMode::kRemote) {
    auto last_file = Clock::now();
    while (total == 0 || report.shots_captured < total) {
      if (!ReportProgress(progress, report.shots_captured, total, "waiting for the camera to fire")) {
        finish("cancelled", "");
        break;
      }
      CameraFilePath added;
      bool got = false;
      int retries = 0;
      CameraStatus st = WithRetry(options.retry, &retries, [&] { return camera.WaitForFileAdded(1.0, &added, &got); });
      report.retries += retries;
      if (!st.ok()) {
        finish(StopReasonFor(st.error), st.message);
        break;
      }
      if (!got || downloaded.count(added.ToString())) {
        if (options.remote_idle_timeout_s > 0 && SecondsSince(last_file) > options.remote_idle_timeout_s) {
          finish("idle_timeout", "");
          break;
        }
        continue;
      }
      // The event wait is the photographer's time, not the camera's: count from the event.
      if (!take(added, Clock::now(), 0.0, 0)) break;
      last_file = Clock::now();
      ReportProgress(progress, report.shots_captured, total,
                     report.shots.back().file + " " + SettingsSummary(report.settings));
    }
  } else {
    auto next_start = Clock::now();
    for (int n = 1; n <= total; ++n) {
      if (options.mode == CaptureMode::kEnter && !ready(n, total)) {
        finish("cancelled", "");
        break;
      }
      if (options.mode == CaptureMode::kInterval) {
        std::this_thread::sleep_until(next_start);
        next_start = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                        std::chrono::duration<double>(options.interval_s));
      }
      const auto t0 = Clock::now();
      CameraFilePath on_card;
      int retries = 0;
      CameraStatus st = WithRetry(options.retry, &retries, [&] { return camera.Capture(&on_card); });
      const double capture_s = SecondsSince(t0);
      if (!st.ok()) {
        report.retries += retries;
        finish(StopReasonFor(st.error), st.message);
        break;
      }
      // capture_s includes retry pauses: they are not mesocap's overhead.
      if (!take(on_card, t0, capture_s, retries)) break;
      if (!ReportProgress(progress, n, total, report.shots.back().file + " " + SettingsSummary(report.settings))) {
        if (n < total) finish("cancelled", "");
        break;
      }
    }
  }
  if (!report.error.empty()) {
    const int in_session = int(session->ShotsOfKind(kind).size());
    report.error += "; " + std::to_string(report.shots_captured) + " shots taken this run, " +
                    std::to_string(in_session) + " in " + root.string() + ", all intact" +
                    (report.stop_reason == "camera_gone" || report.stop_reason == "camera_not_responding"
                         ? "; reconnect the camera and continue with --resume"
                         : report.stop_reason == "card_full" ? "; empty the camera's card and continue with --resume"
                         : report.stop_reason == "disk_full" ? "; free disk space and continue with --resume"
                                                             : "");
  }

  // 5. Timings and the report.
  report.total_s = SecondsSince(t_start);
  for (const auto& s : report.shots) {
    report.mean_camera_s += s.camera_s;
    report.mean_overhead_s += s.overhead_s;
    report.max_overhead_s = std::max(report.max_overhead_s, s.overhead_s);
  }
  if (!report.shots.empty()) {
    report.mean_camera_s /= double(report.shots.size());
    report.mean_overhead_s /= double(report.shots.size());
  }
  // Provenance of this run (a resumed session has several): in the report and in the manifest.
  Json report_json = report.ToJson();
  report_json["provenance"] = MakeProvenance(options.ToJson());
  if (Status st = WriteJsonFile(SessionLayout(root).capture_report(), report_json); !st.ok())
    report.warnings.push_back(st.message());
  Json runs = session->manifest().value("capture_runs", Json::array());
  runs.push_back({{"provenance", report_json["provenance"]},
                  {"camera", report_json["camera"]},
                  {"kind", kind},
                  {"first_index", report.first_index},
                  {"shots_captured", report.shots_captured},
                  {"stop_reason", report.stop_reason}});
  if (Status st = session->UpdateManifest({{"capture_runs", runs}}); !st.ok()) report.warnings.push_back(st.message());
  return report;
}

}  // namespace mesocap

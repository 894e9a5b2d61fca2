#include "capture/simulate.h"

#include <chrono>
#include <cstdio>
#include <future>

#include "capture/rig_material.h"
#include "core/atomic_file.h"
#include "core/image_io.h"
#include "core/progress.h"
#include "core/provenance.h"
#include "core/session.h"
#include "core/session_layout.h"

namespace mesocap {
namespace fs = std::filesystem;

namespace {

}  // namespace

// The virtual camera's clock: deterministic, one shot every 6 seconds.
std::string VirtualClockTime(int k, bool exif) {
  const int seconds = 6 * k, hh = 12 + seconds / 3600, mm = (seconds / 60) % 60, ss = seconds % 60;
  char buf[32];
  std::snprintf(buf, sizeof buf, exif ? "2026:01:01 %02d:%02d:%02d" : "2026-01-01T%02d:%02d:%02dZ", hh, mm, ss);
  return buf;
}

ImageWriteOptions VirtualShotWriteOptions(const std::string& format, bool flash, int k) {
  ImageWriteOptions o;
  o.format = format == "jpg" ? PixelFormat::kUint8Srgb : format == "png" ? PixelFormat::kUint16Linear : PixelFormat::kFloat;
  o.attributes["Make"] = std::string("mesocap");
  o.attributes["Model"] = std::string("virtual rig");
  o.attributes["ExposureTime"] = 1.0f / 125.0f;
  o.attributes["FNumber"] = 8.0f;
  o.attributes["Exif:PhotographicSensitivity"] = 100;
  o.attributes["Exif:Flash"] = flash ? 1 : 0;  // EXIF: bit 0 = flash fired
  o.attributes["DateTime"] = VirtualClockTime(k, true);
  o.attributes["Exif:DateTimeOriginal"] = VirtualClockTime(k, true);
  return o;
}

namespace {

std::string WithExtension(const std::string& file, const std::string& ext) {
  return fs::path(file).replace_extension(ext).string();
}

}  // namespace

std::string ExtensionForFormat(const std::string& format) {
  if (format == "jpg") return ".jpg";
  if (format == "png") return ".png";
  if (format == "exr") return ".exr";
  return "";
}

std::string SimulateOptions::Check() const {
  if (std::string why = rig.Check(); !why.empty()) return why;
  if (std::string why = render.Check(); !why.empty()) return why;
  if (ExtensionForFormat(image_format).empty()) return "--format must be jpg, png or exr";
  if (out.empty()) return "--out is required";
  if (!IsMissingOrEmptyDir(out)) return out.string() + ": exists and is not empty; choose a new folder";
  return "";
}

Json SimulateOptions::ToJson() const {
  Json j = rig.ToJson();
  j["format"] = image_format;
  j["samples_per_axis"] = render.samples_per_axis;
  j["patch_texels"] = render.patch_texels;
  j["out"] = out.string();
  return j;
}

Json SimulateReport::ToJson() const {
  return {{"out", out.string()}, {"shots_written", shots_written}, {"calib_shots_written", calib_shots_written},
          {"prepare_s", prepare_s}, {"per_shot_s", per_shot_s}, {"per_calib_shot_s", per_calib_shot_s},
          {"total_s", total_s}};
}

std::string SimulateReport::Brief() const {
  char buf[256];
  std::snprintf(buf, sizeof buf, "%d shots + %d calibration shots in %.1f s (%.2f s/shot, prepare %.1f s) -> %s",
                shots_written, calib_shots_written, total_s, per_shot_s, prepare_s, out.string().c_str());
  return buf;
}

StatusOr<SimulateReport> SimulateSession(const SimulateOptions& options, const ProgressFn& progress) {
  if (std::string why = options.Check(); !why.empty()) return Status::Error(why);
  const auto t0 = std::chrono::steady_clock::now();
  auto material = Material::Create(options.rig.material);
  if (!material.ok()) return material.status();
  auto scene_or = MakeRigScene(options.rig);
  if (!scene_or.ok()) return scene_or.status();
  RigScene scene = *scene_or;
  const std::string ext = ExtensionForFormat(options.image_format);
  for (auto& s : scene.shots) s.file = WithExtension(s.file, ext);
  for (auto& s : scene.calib_shots) s.file = WithExtension(s.file, ext);

  const fs::path out = fs::absolute(options.out).lexically_normal();
  // The session appears whole at the end; any early return or exception removes the staging.
  auto staged = StagingFolder::Begin(out);
  if (!staged.ok()) return staged.status();
  const fs::path staging = staged->path();
  std::error_code ec;

  Json manifest = {{"source", "virtual"}, {"camera", {{"model", "mesocap virtual rig"}, {"port", "virtual"}}},
                   {"material", options.rig.material}, {"provenance", MakeProvenance(options.ToJson())}};
  auto session = Session::Create(staging, manifest);
  if (!session.ok()) return session.status();
  const SessionLayout layout(staging);
  fs::create_directories(layout.shots(), ec);
  fs::create_directories(layout.calib(), ec);
  if (ec) return Status::Error(staging.string() + ": cannot create folders: " + ec.message());

  RigRenderer renderer(scene, *material, options.render);
  renderer.Prepare();
  SimulateReport report;
  report.prepare_s = SecondsSince(t0);
  const int total = int(scene.calib_shots.size() + scene.shots.size());

  auto write_shot = [&](Image image, const std::string& file, const std::string& kind, int index, int clock,
                        bool flash, uint64_t stream) -> Status {
    renderer.ApplySensor(&image, stream);
    MESOCAP_RETURN_IF_ERROR(WriteImage(staging / file, image, VirtualShotWriteOptions(options.image_format, flash, clock)));
    ShotRecord record;
    record.index = index;
    record.kind = kind;
    record.file = file;
    record.time_utc = VirtualClockTime(clock, false);
    record.settings = {{"iso", 100}, {"shutterspeed", "1/125"}, {"f-number", "f/8"}, {"flash", flash}};
    record.exif = {{"ExposureTime", 1.0 / 125}, {"FNumber", 8.0}, {"ISO", 100}, {"Flash", flash ? 1 : 0}};
    return session->RecordShot(record);
  };
  // A shot is noised, encoded and written while the next one renders: encoding is serial, and
  // would leave the other cores idle. One write at a time keeps the journal in shot order.
  std::future<Status> writing;
  std::string writing_file;
  int written = 0;
  auto finish_writing = [&]() -> Status {  // waits for the write in flight, then reports it
    if (!writing.valid()) return Status::Ok();
    MESOCAP_RETURN_IF_ERROR(writing.get());
    if (!ReportProgress(progress, ++written, total, writing_file)) return Status::Cancelled();
    return Status::Ok();
  };
  auto render_and_write = [&](Image image, const std::string& file, const std::string& kind, int index, int clock,
                              bool flash, uint64_t stream) -> Status {
    MESOCAP_RETURN_IF_ERROR(finish_writing());
    writing_file = file;
    writing = std::async(std::launch::async, [=, &write_shot, image = std::move(image)]() mutable {
      return write_shot(std::move(image), file, kind, index, clock, flash, stream);
    });
    return Status::Ok();
  };

  const auto t_calib = std::chrono::steady_clock::now();
  for (size_t k = 0; k < scene.calib_shots.size(); ++k)
    MESOCAP_RETURN_IF_ERROR(render_and_write(renderer.RenderCalibLinear(int(k)), scene.calib_shots[k].file, "calib",
                                             int(k) + 1, int(k), false, 1'000'000 + k));
  MESOCAP_RETURN_IF_ERROR(finish_writing());
  report.calib_shots_written = int(scene.calib_shots.size());
  if (report.calib_shots_written) report.per_calib_shot_s = SecondsSince(t_calib) / report.calib_shots_written;

  const auto t_shots = std::chrono::steady_clock::now();
  for (size_t k = 0; k < scene.shots.size(); ++k)
    MESOCAP_RETURN_IF_ERROR(render_and_write(renderer.RenderShotLinear(int(k)), scene.shots[k].file, "shot", int(k) + 1,
                                             int(scene.calib_shots.size() + k), true, k));
  MESOCAP_RETURN_IF_ERROR(finish_writing());
  report.shots_written = int(scene.shots.size());
  report.per_shot_s = SecondsSince(t_shots) / report.shots_written;

  if (Status st = WriteJsonFile(layout.truth(), TruthToJson(scene)); !st.ok()) return st;
  if (Status st = WriteJsonFile(layout.rig_layout(), LayoutOf(scene).ToJson()); !st.ok()) return st;
  report.out = out;
  report.total_s = SecondsSince(t0);
  if (Status st = WriteJsonFile(layout.simulate_report(), report.ToJson()); !st.ok()) return st;

  // Only now does the session appear under its name.
  if (Status st = staged->Publish(); !st.ok()) return st;
  return report;
}

}  // namespace mesocap

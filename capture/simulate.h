// `mesocap simulate`: renders a complete capture session of the virtual rig into a session
// folder (shots/, calib/, journal, manifest) plus truth.json, deterministically per seed.
#pragma once

#include <filesystem>
#include <string>

#include "capture/rig_render.h"
#include "capture/rig_scene.h"
#include "core/image_io.h"
#include "core/json.h"
#include "core/progress.h"
#include "core/status.h"

namespace mesocap {

struct SimulateOptions {
  RigOptions rig;
  RigRenderOptions render;
  std::string image_format = "jpg";  // jpg (8-bit sRGB), png (16-bit linear), exr (float linear)
  std::filesystem::path out;

  std::string Check() const;  // empty when valid
  Json ToJson() const;
};

struct SimulateReport {
  std::filesystem::path out;
  int shots_written = 0, calib_shots_written = 0;
  double prepare_s = 0, total_s = 0, per_shot_s = 0, per_calib_shot_s = 0;
  Json ToJson() const;
  std::string Brief() const;
};

// Renders into a hidden staging folder beside `out` and renames it into place only when every
// file is written, so an interrupted or failed run never leaves a session that looks complete.
StatusOr<SimulateReport> SimulateSession(const SimulateOptions& options, const ProgressFn& progress = nullptr);

// How a virtual shot is written: pixel format for `format` and the EXIF a camera would add.
// `clock` numbers the shot on the virtual camera's clock (one shot every 6 s), so the bytes never
// depend on the wall clock.
ImageWriteOptions VirtualShotWriteOptions(const std::string& format, bool flash, int clock);
std::string VirtualClockTime(int clock, bool exif_format);

// Extension for an image format name ("jpg" -> ".jpg"); empty when unknown.
std::string ExtensionForFormat(const std::string& format);

}  // namespace mesocap

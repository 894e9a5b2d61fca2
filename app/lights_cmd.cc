// mesocap lights: light directions from one reflective sphere in a folder of RTI photos
// (calib/sphere_lights.h), written as a .lp file with a JSON report beside it.
#include "app/lights_args.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "app/commands.h"
#include "core/atomic_file.h"
#include "calib/sphere_lights.h"
#include "core/image_io.h"
#include "core/json.h"
#include "core/provenance.h"
#include "formats/lp_file.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;

bool ParseCircle(const std::string& text, SphereCircle* circle) {
  std::string s = text;
  std::replace(s.begin(), s.end(), ',', ' ');
  std::istringstream in(s);
  double x, y, r;
  std::string rest;
  if (!(in >> x >> y >> r) || (in >> rest)) return false;
  *circle = {{x, y}, r};
  return std::isfinite(x) && std::isfinite(y) && std::isfinite(r) && r > 2;
}

}  // namespace

int RunLights(const LightsArgs& a) {
  const std::string verb = "lights";
  if (a.sphere_mask.empty() == a.sphere.empty()) return Fail(verb, "give exactly one of --sphere-mask and --sphere", kExitUsage);
  if (std::string why = a.options.Check(); !why.empty()) return Fail(verb, why, kExitUsage);
  const fs::path folder = a.images;
  if (!fs::is_directory(folder)) return Fail(verb, "--images " + a.images + ": not a folder", kExitUsage);
  const fs::path out = a.out.empty() ? folder / "lights.lp" : fs::path(a.out);
  if (out.extension() != ".lp") return Fail(verb, "--out must end in .lp: " + out.string(), kExitUsage);

  SphereCircle circle;
  int mask_width = 0, mask_height = 0;
  if (!a.sphere.empty()) {
    if (!ParseCircle(a.sphere, &circle)) return Fail(verb, "--sphere must be x,y,r in pixels (r > 2), not '" + a.sphere + "'", kExitUsage);
  } else {
    // Mask values are coverage: read 8-bit files without sRGB decoding.
    auto mask = ReadImage(a.sphere_mask, {.linearize = false});
    if (!mask.ok()) return Fail(verb, mask.status());
    auto c = CircleFromMask(*mask);
    if (!c.ok()) return Fail(verb, a.sphere_mask + ": " + c.status().message());
    circle = *c;
    mask_width = mask->width();
    mask_height = mask->height();
  }

  std::vector<fs::path> photos;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(folder, ec))
    if (e.is_regular_file() && HasReadableImageExtension(e.path()) &&
        (a.sphere_mask.empty() || !fs::equivalent(e.path(), a.sphere_mask, ec)))
      photos.push_back(e.path());
  if (ec) return Fail(verb, folder.string() + ": " + ec.message());
  std::sort(photos.begin(), photos.end());
  if (photos.empty()) return Fail(verb, folder.string() + ": no photos (.jpg, .png, .tif, .exr)");

  std::vector<LpEntry> entries;
  Json per_photo = Json::array();
  int skipped = 0;
  for (const fs::path& p : photos) {
    SphereLight light;
    auto im = ReadImage(p);
    if (!im.ok()) light.why_not = "unreadable: " + im.status().message();
    else if (mask_width > 0 && (im->width() != mask_width || im->height() != mask_height))
      light.why_not = "size " + std::to_string(im->width()) + "x" + std::to_string(im->height()) + " differs from the mask's " +
                      std::to_string(mask_width) + "x" + std::to_string(mask_height);
    else light = FindSphereLight(*im, circle, a.options);
    Json j = light.ToJson();
    j["file"] = p.filename().string();
    per_photo.push_back(j);
    if (light.found) {
      entries.push_back({p, light.light_dir});
    } else {
      ++skipped;
      std::fprintf(stderr, "mesocap lights: skipped %s: %s\n", p.filename().string().c_str(), light.why_not.c_str());
    }
  }

  const fs::path report_path = fs::path(out).replace_extension(".json");
  Json report = {{"sphere", circle.ToJson()},
                 {"photos", photos.size()},
                 {"lights", entries.size()},
                 {"skipped", skipped},
                 {"lp_file", out.string()},
                 {"per_photo", per_photo},
                 {"provenance", MakeProvenance({{"images", a.images}, {"sphere_mask", a.sphere_mask}, {"sphere", a.sphere},
                                                {"out", out.string()}, {"saturation", a.options.saturation},
                                                {"blob_level", a.options.blob_level},
                                                {"min_peak_over_median", a.options.min_peak_over_median},
                                                {"max_blob_radius", a.options.max_blob_radius},
                                                {"max_rim_radius", a.options.max_rim_radius}})}};
  if (!out.parent_path().empty()) fs::create_directories(out.parent_path(), ec);
  // The report is written even when too few photos are lit: it holds the reasons. Otherwise the
  // .lp and its report appear together.
  OutputFileSet outputs;
  if (entries.size() >= 3)
    if (Status s = outputs.Stage(out, [&](const fs::path& temp) { return WriteLpFile(temp, entries); }); !s.ok())
      return Fail(verb, s);
  if (Status s = outputs.Stage(report_path, [&](const fs::path& temp) { return WriteJsonFile(temp, report); }); !s.ok())
    return Fail(verb, s);
  if (Status s = outputs.Commit(); !s.ok()) return Fail(verb, s);
  if (entries.size() < 3)
    return Fail(verb, "only " + std::to_string(entries.size()) + " of " + std::to_string(photos.size()) +
                          " photos show a usable highlight (need 3); reasons in " + report_path.string());
  std::printf("lights: sphere at (%.2f, %.2f) r %.2f px; %zu of %zu photos lit, %d skipped -> %s (report %s)\n",
              circle.centre_px.x(), circle.centre_px.y(), circle.radius_px, entries.size(), photos.size(), skipped,
              out.string().c_str(), report_path.string().c_str());
  return kExitOk;
}
}  // namespace mesocap::app

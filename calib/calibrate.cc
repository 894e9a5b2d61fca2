#include "calib/calibrate.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>

#include "calib/marked_corners.h"
#include "calib/shot_accumulator.h"
#include "core/image_io.h"
#include "core/parallel.h"
#include "core/session.h"

namespace mesocap {
namespace fs = std::filesystem;

SphereOptions SphereOptionsFor(const RigLayout& layout) {
  SphereOptions options;
  options.radius_m = layout.sphere_radius_m;
  options.expected_count = layout.sphere_count;
  return options;
}

std::string CalibrateOptions::Check() const {
  if (session.empty()) return "a session folder is required";
  if (pose_shots < 1) return "--pose-shots must be at least 1";
  return "";
}

int CalibrationResult::usable_shots() const {
  return int(std::count_if(shots.begin(), shots.end(), [](const ShotCalibration& s) { return s.light.ok; }));
}

Json CalibrationResult::RigJson() const {
  Json j = {{"format", "mesocap-rig"}, {"format_version", 1},
            {"frame", "camera (OpenCV: x right, y down, z forward), metres"}, {"camera", camera.ToJson()}};
  j["boards"] = Json::array();
  for (const auto& b : boards) j["boards"].push_back(b.ToJson());
  j["spheres"] = Json::array();
  for (const auto& s : spheres.spheres) j["spheres"].push_back(s.ToJson());
  j["grey_cards"] = Json::array();
  for (const auto& c : grey_cards) j["grey_cards"].push_back(c.ToJson());
  j["shots"] = Json::array();
  for (const auto& s : shots) {
    Json js = {{"file", s.file}, {"ok", s.light.ok}};
    if (s.light.ok) {
      js["light_m"] = ToJson(s.light.light_m);
      js["light_stddev_mm"] = 1000 * std::sqrt(s.light.covariance_m2.trace());
    }
    js["power"] = s.power;
    js["power_x_exposure"] = s.power_x_exposure;
    if (!s.flag.empty()) js["flag"] = s.flag;
    j["shots"].push_back(js);
  }
  return j;
}

CalibrationResult CalibrationResult::FromRigJson(const Json& j) {
  constexpr double kMetres = 1e3, kPixels = 1e6;
  CalibrationResult r;
  try {
    r.camera = CameraModel::FromJson(JsonField(j, "", "camera"));
  } catch (const JsonFieldError& e) {
    throw JsonFieldError(std::string("camera: ") + e.what());
  }
  const Json& boards = JsonArray(JsonField(j, "", "boards"), "boards", 0, 1000);
  for (size_t k = 0; k < boards.size(); ++k) {
    const std::string path = JsonIndexPath("boards", k);
    BoardPose b;
    b.id = JsonInteger(JsonField(boards[k], path, "id"), JsonFieldPath(path, "id"), 0, 1 << 20);
    b.found = JsonBool(JsonField(boards[k], path, "found"), JsonFieldPath(path, "found"));
    if (b.found) {
      // The pose's figures: any non-negative size (a poorly constrained board's spread may be
      // large), and NaN where the writer had none to give (JSON null).
      const auto number = [&](const char* name) {
        const Json& field = JsonField(boards[k], path, name);
        return field.is_null() ? std::numeric_limits<double>::quiet_NaN()
                               : JsonNumber(field, JsonFieldPath(path, name), 0, std::numeric_limits<double>::max());
      };
      b.R = JsonMatrix3d(JsonField(boards[k], path, "R"), JsonFieldPath(path, "R"), 1.5);
      b.t = JsonVector3d(JsonField(boards[k], path, "t"), JsonFieldPath(path, "t"), kMetres);
      b.corners_used = JsonInteger(JsonField(boards[k], path, "corners_used"), JsonFieldPath(path, "corners_used"), 0, 1 << 30);
      b.shots_seen = JsonInteger(JsonField(boards[k], path, "shots_seen"), JsonFieldPath(path, "shots_seen"), 0, 1 << 30);
      b.rms_reprojection_px = number("rms_reprojection_px");
      b.rotation_stddev_deg = number("rotation_stddev_deg");
      b.translation_stddev_mm = number("translation_stddev_mm");
    } else if (boards[k].contains("why_not")) {
      b.why_not = JsonString(boards[k]["why_not"], JsonFieldPath(path, "why_not"));
    }
    r.boards.push_back(b);
  }
  const Json& spheres = JsonArray(JsonField(j, "", "spheres"), "spheres", 0, 1000);
  for (size_t k = 0; k < spheres.size(); ++k) {
    const std::string path = JsonIndexPath("spheres", k);
    SphereEstimate s;
    s.center_m = JsonVector3d(JsonField(spheres[k], path, "center_m"), JsonFieldPath(path, "center_m"), kMetres);
    s.radius_m = JsonNumber(JsonField(spheres[k], path, "radius_m"), JsonFieldPath(path, "radius_m"), 0, kMetres);
    s.image_centre_px = JsonVector2d(JsonField(spheres[k], path, "image_centre_px"), JsonFieldPath(path, "image_centre_px"), kPixels);
    s.image_radius_px = JsonNumber(JsonField(spheres[k], path, "image_radius_px"), JsonFieldPath(path, "image_radius_px"), 0, kPixels);
    r.spheres.spheres.push_back(s);
  }
  const Json& cards = JsonArray(JsonField(j, "", "grey_cards"), "grey_cards", 0, 1000);
  for (size_t k = 0; k < cards.size(); ++k) {
    const std::string path = JsonIndexPath("grey_cards", k);
    GreyCard c;
    c.R = JsonMatrix3d(JsonField(cards[k], path, "R"), JsonFieldPath(path, "R"), 1.5);
    c.t = JsonVector3d(JsonField(cards[k], path, "t"), JsonFieldPath(path, "t"), kMetres);
    c.size_m = JsonNumber(JsonField(cards[k], path, "size_m"), JsonFieldPath(path, "size_m"), 0, kMetres);
    c.albedo = JsonNumber(JsonField(cards[k], path, "albedo"), JsonFieldPath(path, "albedo"), 0, 1);
    r.grey_cards.push_back(c);
  }
  const Json& shots = JsonArray(JsonField(j, "", "shots"), "shots", 0, 1 << 20);
  for (size_t k = 0; k < shots.size(); ++k) {
    const std::string path = JsonIndexPath("shots", k);
    ShotCalibration s;
    s.file = JsonRelativePath(JsonField(shots[k], path, "file"), JsonFieldPath(path, "file")).generic_string();
    s.light.ok = JsonBool(JsonField(shots[k], path, "ok"), JsonFieldPath(path, "ok"));
    if (s.light.ok)
      s.light.light_m = JsonVector3d(JsonField(shots[k], path, "light_m"), JsonFieldPath(path, "light_m"), kMetres);
    s.power = JsonNumber(JsonField(shots[k], path, "power"), JsonFieldPath(path, "power"), 0, 1e12);
    s.power_x_exposure = JsonNumber(JsonField(shots[k], path, "power_x_exposure"), JsonFieldPath(path, "power_x_exposure"), 0, 1e12);
    if (shots[k].contains("flag")) s.flag = JsonString(shots[k]["flag"], JsonFieldPath(path, "flag"));
    r.shots.push_back(s);
  }
  return r;
}

Json CalibrationResult::ReportJson() const {
  Json shots_json = Json::array();
  for (const auto& s : shots) {
    Json cards_json = Json::array();
    for (const auto& c : s.cards)
      cards_json.push_back({{"usable", c.usable}, {"variation", c.variation}, {"power_x_exposure", c.power_x_exposure},
                            {"why_not", c.why_not}});
    shots_json.push_back({{"file", s.file}, {"light", s.light.ToJson()}, {"cards", cards_json}, {"flag", s.flag}});
  }
  return {{"seconds_total", seconds_total}, {"usable_shots", usable_shots()}, {"shots_total", shots.size()},
          {"rejected", rejected}, {"rejected_blobs", spheres.rejected_blobs}, {"shots", shots_json}};
}

std::vector<std::string> CalibrationResult::RejectedFromReportJson(const Json& j) {
  const Json& list = JsonArray(JsonField(j, "", "rejected"), "rejected", 0, 1 << 20);
  std::vector<std::string> rejected;
  for (size_t k = 0; k < list.size(); ++k) rejected.push_back(JsonString(list[k], JsonIndexPath("rejected", k)));
  return rejected;
}

std::string CalibrationResult::Brief() const {
  int boards_found = 0;
  for (const auto& b : boards) boards_found += b.found;
  char buf[256];
  std::snprintf(buf, sizeof buf, "%d/%zu boards posed, %zu balls, %zu grey cards, %d/%zu shots with a flash position, %.1f s",
                boards_found, boards.size(), spheres.spheres.size(), grey_cards.size(), usable_shots(), shots.size(),
                seconds_total);
  return buf;
}

StatusOr<CalibrationResult> CalibrateSession(const CalibrateOptions& options, const RigLayout& layout,
                                             const CameraModel& camera, const ProgressFn& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  if (std::string why = options.Check(); !why.empty()) return Status::Error(why);
  auto session = Session::Open(options.session);
  if (!session.ok()) return session.status();
  const std::vector<ShotRecord> records = session->ShotsOfKind("shot");
  if (records.empty()) return Status::Error(options.session.string() + ": the session has no flash shots");
  CalibrationResult result;
  result.camera = camera;
  const int n = int(records.size());

  std::map<std::string, std::vector<TagDetection>> marked;
  if (!options.marked_corners.empty()) {
    auto read = ReadMarkedCorners(options.marked_corners, layout.boards, camera.width, camera.height);
    if (!read.ok()) return read.status();
    marked = std::move(*read);
  }
  const std::vector<LayoutBoard> boards = marked.empty() ? layout.boards : WithOutlineTags(layout.boards);

  // Pass 1: decode every shot once for the per-pixel maximum; detect tags on a spread subset.
  const int step = std::max(1, n / options.pose_shots);
  std::vector<std::vector<TagDetection>> detections(n);
  ShotAccumulator accumulated;
  std::vector<std::string> unreadable(n);
  std::atomic<int> done{0};
  std::atomic<bool> cancelled{false};
  ParallelFor(0, n, [&](int s) {
    if (cancelled) return;
    auto im = ReadImage(options.session / records[s].file);
    if (!im.ok()) {
      unreadable[s] = im.status().message();
      return;
    }
    if (s % step == 0) detections[s] = DetectTags(*im, options.tags);
    if (auto it = marked.find(fs::path(records[s].file).generic_string()); it != marked.end())
      detections[s].insert(detections[s].end(), it->second.begin(), it->second.end());
    accumulated.Add(*im);
    if (!ReportProgress(progress, ++done, 2 * n, records[s].file)) cancelled = true;
  }, options.num_threads);
  if (cancelled) return Status::Cancelled();
  if (accumulated.empty()) return Status::Error(options.session.string() + ": no flash shot could be read");
  const Image sum_image = accumulated.Sum(), max_image = accumulated.TakeMax();
  for (int s = 0; s < n; ++s)
    if (!unreadable[s].empty()) result.rejected.push_back(unreadable[s]);

  result.boards = EstimateBoardPoses(camera, boards, detections, options.poses);
  for (const auto& b : result.boards)
    if (!b.found) result.rejected.push_back("board " + std::to_string(b.id) + ": " + b.why_not);
  result.spheres = LocateSpheres(camera, max_image, sum_image, SphereOptionsFor(layout));  // a sum is a scaled mean
  if (int(result.spheres.spheres.size()) != layout.sphere_count)
    result.rejected.push_back("found " + std::to_string(result.spheres.spheres.size()) + " of " +
                              std::to_string(layout.sphere_count) + " balls");
  // Grey cards sit on tagged mounts: posed exactly like the boards.
  const std::vector<BoardPose> mounts = EstimateBoardPoses(camera, layout.grey_cards, detections, options.poses);
  for (size_t k = 0; k < mounts.size(); ++k) {
    if (!mounts[k].found) {
      result.rejected.push_back("grey card " + std::to_string(k) + ": " + mounts[k].why_not);
      continue;
    }
    result.grey_cards.push_back({mounts[k].R, mounts[k].t, layout.grey_cards[k].patch_m, layout.grey_card_albedo});
  }
  if (result.spheres.spheres.size() < 2)
    return Status::Error(options.session.string() + ": fewer than 2 balls found; cannot locate the flash");

  // Pass 2: per shot, the flash from the highlights and the grey cards' readings.
  result.shots.resize(n);
  ParallelFor(0, n, [&](int s) {
    if (cancelled) return;
    ShotCalibration& sc = result.shots[s];
    sc.file = records[s].file;
    if (!unreadable[s].empty()) {
      sc.flag = "unreadable";
      return;
    }
    auto im = ReadImage(options.session / records[s].file);
    if (!im.ok()) {
      sc.flag = im.status().message();
      return;
    }
    sc.light = EstimateFlash(camera, result.spheres.spheres, *im, options.highlights);
    if (!sc.light.ok) sc.flag = sc.light.flag;
    else sc.cards = ReadGreyCards(camera, result.grey_cards, *im, sc.light.light_m);
    if (!ReportProgress(progress, ++done, 2 * n, records[s].file)) cancelled = true;
  }, options.num_threads);
  if (cancelled) return Status::Cancelled();

  std::vector<std::vector<CardReading>> readings;
  std::vector<int> index;
  for (int s = 0; s < n; ++s)
    if (result.shots[s].light.ok) {
      readings.push_back(result.shots[s].cards);
      index.push_back(s);
    }
  std::vector<std::string> power_flags;
  const std::vector<double> power = CombineCardReadings(readings, &power_flags);
  double mean = 0;
  for (double p : power) mean += p;
  mean = power.empty() ? 0 : mean / power.size();
  for (size_t k = 0; k < index.size(); ++k) {
    ShotCalibration& sc = result.shots[index[k]];
    sc.power_x_exposure = power[k];
    sc.power = mean > 0 ? power[k] / mean : 0;
    if (!power_flags[k].empty()) sc.flag = power_flags[k];
  }
  for (const auto& sc : result.shots)
    if (!sc.flag.empty()) result.rejected.push_back(sc.file + ": " + sc.flag);
  result.seconds_total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (result.usable_shots() == 0)
    return Status::Error(options.session.string() + ": no shot has a usable flash position (highlights missing)");
  return result;
}

}  // namespace mesocap

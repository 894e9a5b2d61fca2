// Guidance during tethered capture (`mesocap capture --guide`): after each flash shot, where the
// flash was and what the session still needs. The boards and balls are located once, by a full
// calibration of the first flash shots (they never move); each later shot only reads its
// highlights on the balls (calib/flash_lights.h), so guidance takes seconds, not a calibration.
// A ball the first shots did not show (no shot lit it yet) is looked for again in the per-pixel
// maximum of the shots as they arrive, as `calibrate` looks for the balls in all of them.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/coverage_output.h"
#include "app/shot_checks.h"
#include "calib/calibrate.h"
#include "calib/shot_accumulator.h"
#include "core/rig_layout.h"

namespace mesocap::app {

struct CaptureGuideOptions {
  std::filesystem::path session;
  std::filesystem::path layout_file;  // empty: SESSION/rig_layout.json
  std::filesystem::path camera_file;  // intrinsics; empty: from the session's checkerboard shots
  int locate_after_shots = 6;         // flash shots before the boards and balls are located
  CoverageOptions coverage;
  ShotCheckOptions checks;
  std::string Check() const;  // empty when valid
};

struct ShotGuidance {
  std::string shot;  // relative to the session
  std::optional<Eigen::Vector3d> flash_cam;  // where the flash was, when the balls showed it
  std::string flash_words;                   // ... in the operator's words
  std::vector<std::string> missing;          // what keeps the guidance from being complete
  std::vector<std::string> warnings;         // the shot's own problems (shot_checks.h): overexposed, blurred, ...
  std::string rig_news;                      // balls found after the rig was located
  std::optional<CoverageAssessment> coverage;
  double seconds = 0;                        // this shot's guidance, reading the photo included
  std::string Text() const;                  // the lines printed after the shot
};

class CaptureGuide {
 public:
  // Reads the layout and the intrinsics (calibrating them from the session's checkerboard shots
  // when no camera file is given).
  static StatusOr<std::unique_ptr<CaptureGuide>> Start(const CaptureGuideOptions& options);

  // Guidance after `shot` (relative to the session) was added. Also writes SESSION/coverage/.
  ShotGuidance AfterShot(const std::string& shot);
  // Guidance after `shot` was rejected (the operator's undo): its flash no longer counts.
  ShotGuidance AfterUndo(const std::string& shot);

  bool rig_located() const { return located_; }
  const CalibrationResult& rig() const { return rig_; }
  // Flash positions so far (camera frame) by shot file: from the locating calibration, then quick.
  const std::map<std::string, Eigen::Vector3d>& flashes() const { return flashes_; }

 private:
  CaptureGuide() = default;
  // A full calibration of the shots so far: board poses, balls and their flashes.
  void LocateRig(std::vector<std::string>* missing);
  // Balls the layout has and the rig lacks: looked for in every shot so far, and once more when
  // the shots have doubled after they are all found.
  bool BallsMissing() const { return located_ && int(rig_.spheres.spheres.size()) < layout_.sphere_count; }
  bool SearchingForBalls() const { return BallsMissing() || balls_settle_at_ > 0; }
  std::vector<std::string> ShotsSoFar() const;  // the session's flash shots, as recorded
  void ReadShots(const std::vector<std::string>& files, const std::function<void(size_t, const Image&)>& use) const;
  void AddShotsSoFar();
  void SearchForBalls(int shots, ShotGuidance* g);
  void AdoptBalls(SphereReport balls);
  std::optional<Eigen::Vector3d> QuickFlash(const Image& image, std::string* why_not) const;
  CoverageAssessment Assess() const;
  void Conclude(ShotGuidance* g);

  CaptureGuideOptions options_;
  RigLayout layout_;
  CameraModel camera_;
  CalibrationResult rig_;
  bool located_ = false;
  int next_locate_at_ = 0;  // flash shots in the session when locating is (re)tried
  // While balls are searched for: the shots so far (their maximum shows every ball some flash
  // lit), when the search is next tried, and when the balls found late are found again.
  ShotAccumulator shots_seen_;
  int next_ball_search_at_ = 0;
  int balls_settle_at_ = 0;
  std::map<std::string, Eigen::Vector3d> flashes_;
  LitFn lit_;  // shadows cast by the rig, as located
  FlashUsableFn usable_;  // positions calibration can locate the flash from and read its power at
  // First suggestions after which the next shot gave no flash position: not suggested again (the
  // operator, or the virtual photographer, went there and it failed).
  std::vector<Eigen::Vector3d> failed_suggestions_;
  std::optional<Eigen::Vector3d> last_suggestion_;
  std::vector<double> sharpness_;  // TopBoardSharpness of the shots checked so far
};

}  // namespace mesocap::app

#include "app/capture_guide.h"

#include <algorithm>
#include <chrono>
#include <functional>

#include "app/rig_plot.h"
#include "app/session_stages.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "core/parallel.h"
#include "core/session.h"
#include "core/session_layout.h"
#include "core/text_format.h"
#include "reconstruct/slice_set.h"

namespace mesocap::app {

namespace fs = std::filesystem;

namespace {

// A suggestion whose shot failed rules out the positions within this of it, seen from the top
// board (the guidance's grid steps are 5 deg in elevation and 10 in azimuth).
constexpr double kFailedSuggestionDeg = 10;

std::vector<Eigen::Vector3d> Positions(const std::map<std::string, Eigen::Vector3d>& flashes) {
  std::vector<Eigen::Vector3d> positions;
  for (const auto& [file, position] : flashes) positions.push_back(position);
  return positions;
}

// Every line of `lines` indented by two spaces.
std::string Indented(const std::string& lines) {
  std::string text = "  ";
  for (char c : lines) text += c == '\n' ? std::string("\n  ") : std::string(1, c);
  return text;
}

}  // namespace

std::string CaptureGuideOptions::Check() const {
  if (locate_after_shots < 1 || locate_after_shots > 1000) return "--guide-after must be between 1 and 1000 shots";
  if (!(coverage.near_deg > 0 && coverage.near_deg <= 90)) return "--near-deg must be in (0, 90]";
  if (coverage.suggestions < 1 || coverage.suggestions > 100) return "--suggest must be between 1 and 100";
  return "";
}

StatusOr<std::unique_ptr<CaptureGuide>> CaptureGuide::Start(const CaptureGuideOptions& options) {
  if (std::string why = options.Check(); !why.empty()) return Status::Error(why);
  std::unique_ptr<CaptureGuide> guide(new CaptureGuide());
  guide->options_ = options;
  guide->next_locate_at_ = options.locate_after_shots;
  auto layout = LoadSessionLayout(options.session, options.layout_file);
  if (!layout.ok()) return layout.status();
  guide->layout_ = std::move(*layout);
  CalibrateStageOptions stage;
  stage.calibrate.session = options.session;
  stage.camera_file = options.camera_file;
  stage.progress = false;
  Json report;
  Image plot;
  auto camera = CameraFor(stage, guide->layout_, &report, &plot);
  if (!camera.ok())
    return Status::Error(camera.status().message() +
                         " (take the checkerboard shots first with --calibration, or give --camera-file)");
  guide->camera_ = *camera;
  return guide;
}

void CaptureGuide::LocateRig(std::vector<std::string>* missing) {
  CalibrateOptions calibrate;
  calibrate.session = options_.session;
  auto result = CalibrateSession(calibrate, layout_, camera_);
  if (!result.ok()) {
    missing->push_back("the rig is not located yet: " + result.status().message());
    return;
  }
  if (!TopBoardPose(*result)) {
    missing->push_back("no board is located yet: are the boards' AprilTags in view and lit?");
    return;
  }
  rig_ = std::move(*result);
  located_ = true;
  lit_ = ShadowFreeTest(rig_, layout_);
  usable_ = FlashUsableTest(rig_, layout_);
  for (const ShotCalibration& shot : rig_.shots)
    if (shot.light.ok) flashes_[shot.file] = shot.light.light_m;
  if (BallsMissing()) AddShotsSoFar();
}

std::vector<std::string> CaptureGuide::ShotsSoFar() const {
  std::vector<std::string> files;
  if (auto session = Session::Open(options_.session); session.ok())
    for (const ShotRecord& record : session->ShotsOfKind("shot")) files.push_back(record.file);
  return files;
}

// Each readable shot of `files`, read in parallel and handed to `use` with its index.
void CaptureGuide::ReadShots(const std::vector<std::string>& files, const std::function<void(size_t, const Image&)>& use) const {
  ParallelFor(0, int(files.size()), [&](int s) {
    if (auto image = ReadImage(options_.session / files[size_t(s)]); image.ok()) use(size_t(s), *image);
  });
}

void CaptureGuide::AddShotsSoFar() {
  const std::vector<std::string> files = ShotsSoFar();
  ReadShots(files, [&](size_t, const Image& image) { shots_seen_.Add(image); });
  next_ball_search_at_ = int(files.size()) + 1;
}

// Balls are found in the per-pixel maximum: one no flash lit yet shows once a shot lights it. The
// search is a fraction of a calibration, tried after a growing number of shots (a layout may
// count a ball the table lacks). A ball one shot lit is outlined roughly (in the mean, it stands
// out from the table only in that shot), so once all are found they are found once more when the
// shots have doubled, as `calibrate` will find them from those shots.
void CaptureGuide::SearchForBalls(int shots, ShotGuidance* g) {
  const bool settling = !BallsMissing();
  if (shots >= next_ball_search_at_ && !shots_seen_.empty()) {
    next_ball_search_at_ = shots + std::max(1, shots / 4);
    SphereReport found = LocateSpheres(camera_, shots_seen_.max(), shots_seen_.Sum(), SphereOptionsFor(layout_));
    if (found.spheres.size() > rig_.spheres.spheres.size() ||
        (settling && found.spheres.size() == rig_.spheres.spheres.size())) {
      if (!settling)
        g->rig_news = Format("found %zu of %d balls (%zu before)", found.spheres.size(), layout_.sphere_count,
                             rig_.spheres.spheres.size());
      AdoptBalls(std::move(found));
      if (settling) {
        balls_settle_at_ = 0;
        shots_seen_.Clear();  // not needed again: frees two images' worth
      } else if (!BallsMissing()) {
        balls_settle_at_ = next_ball_search_at_ = 2 * shots;
      }
    }
  }
  if (BallsMissing())
    g->missing.push_back(Format("found %zu of %d balls: the flash positions rest on those; the others are looked for "
                                "as the shots light them",
                                rig_.spheres.spheres.size(), layout_.sphere_count));
}

// Every shot so far read again on the new balls: flashes found on fewer are less sure, and shots
// and suggestions that failed for want of a ball may not fail now.
void CaptureGuide::AdoptBalls(SphereReport balls) {
  rig_.spheres = std::move(balls);
  lit_ = ShadowFreeTest(rig_, layout_);
  usable_ = FlashUsableTest(rig_, layout_);
  failed_suggestions_.clear();
  flashes_.clear();
  const std::vector<std::string> files = ShotsSoFar();
  std::vector<std::optional<Eigen::Vector3d>> found(files.size());
  ReadShots(files, [&](size_t s, const Image& image) {
    std::string why_not;
    found[s] = QuickFlash(image, &why_not);
  });
  for (size_t s = 0; s < files.size(); ++s)
    if (found[s]) flashes_[files[s]] = *found[s];
}

std::optional<Eigen::Vector3d> CaptureGuide::QuickFlash(const Image& image, std::string* why_not) const {
  const LightEstimate light = EstimateFlash(camera_, rig_.spheres.spheres, image);
  if (!light.ok) {
    *why_not = "no flash position: " + light.flag + " on the balls (did the flash fire? are the balls in view?)";
    return std::nullopt;
  }
  return light.light_m;
}

CoverageAssessment CaptureGuide::Assess() const {
  const std::vector<Eigen::Vector3d> positions = Positions(flashes_);
  const BoardPose* top = TopBoardPose(rig_);
  const FlashUsableFn usable = [&](const Eigen::Vector3d& flash) {
    for (const Eigen::Vector3d& failed : failed_suggestions_)
      if (AngleBetweenDeg(failed - top->t, flash - top->t) < kFailedSuggestionDeg) return false;
    return usable_(flash);
  };
  return AssessBoards(BoardLightsFromFlashes(rig_.boards, positions, lit_), top->id, positions, options_.coverage,
                      SuggestableTest(lit_, usable));
}

ShotGuidance CaptureGuide::AfterShot(const std::string& shot) {
  const auto t0 = std::chrono::steady_clock::now();
  ShotGuidance g;
  g.shot = shot;
  // The session's journal is read only while locating or searching for balls.
  const int shots = !located_ || SearchingForBalls() ? int(ShotsSoFar().size()) : 0;
  if (!located_) {
    if (shots < next_locate_at_) {
      g.missing.push_back(Format("the boards and balls are located after %d flash shots (%d so far): move the flash "
                                 "all around the target",
                                 next_locate_at_, shots));
    } else {
      LocateRig(&g.missing);
      // A failed attempt is a full calibration: the next waits for a few more shots.
      if (!located_) next_locate_at_ = shots + std::max(1, options_.locate_after_shots / 2);
    }
  } else {
    std::string why_not;
    auto image = ReadImage(options_.session / shot);
    std::optional<Eigen::Vector3d> flash;
    if (!image.ok()) why_not = image.status().message();
    else flash = QuickFlash(*image, &why_not);
    if (image.ok()) {
      const double sharpness = TopBoardSharpness(*image, rig_, layout_);
      g.warnings = CheckShot(*image, rig_, layout_, flash, sharpness_, sharpness, options_.checks);
      if (sharpness > 0) sharpness_.push_back(sharpness);
    }
    if (flash) {
      flashes_[shot] = *flash;
    } else {
      g.missing.push_back(shot + ": " + why_not);
      if (last_suggestion_) failed_suggestions_.push_back(*last_suggestion_);
    }
    if (SearchingForBalls() && image.ok()) shots_seen_.Add(*image);
  }
  if (SearchingForBalls()) SearchForBalls(shots, &g);
  Conclude(&g);
  g.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return g;
}

ShotGuidance CaptureGuide::AfterUndo(const std::string& shot) {
  const auto t0 = std::chrono::steady_clock::now();
  ShotGuidance g;
  g.shot = shot;
  flashes_.erase(shot);
  if (!located_) g.missing.push_back(shot + ": left out");
  Conclude(&g);
  g.flash_cam.reset();
  g.flash_words.clear();
  g.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return g;
}

// Once the rig is located: where the shot's flash was, the coverage of every flash so far and the
// next suggestions, also written to SESSION/coverage/.
void CaptureGuide::Conclude(ShotGuidance* guidance) {
  ShotGuidance& g = *guidance;
  const std::string& shot = g.shot;
  if (located_) {
    if (auto it = flashes_.find(shot); it != flashes_.end()) {
      g.flash_cam = it->second;
      const BoardPose* top = TopBoardPose(rig_);
      g.flash_words = FlashPositionWords(it->second, {top->id, top->R, top->t, {}});
    }
    g.coverage = Assess();
    last_suggestion_.reset();
    if (!g.coverage->report.next.empty()) last_suggestion_ = g.coverage->report.next.front().position_cam;
    for (const BoardCoverage& b : g.coverage->report.boards)
      if (b.lights < kMinSlicesPerView)
        g.missing.push_back(Format("board %d has %d usable light(s) of the %d its reconstruction needs", b.board, b.lights,
                                   kMinSlicesPerView));
    // Where each shot's flash was found, for the operator's log (and to check against calibrate).
    Json flashes = Json::array();
    for (const auto& [file, p] : flashes_) flashes.push_back({{"shot", file}, {"position_cam_m", ToJson(p)}});
    if (Status st = WriteCoverageFolder(SessionLayout(options_.session).coverage().root, *g.coverage, "capture guidance",
                                        {{"session", options_.session.string()}, {"after_shot", shot},
                                         {"images", HeldImagesWords(options_.coverage.images)}},
                                        {{"flashes", flashes}});
        !st.ok())
      g.missing.push_back(st.message());
  }
}

std::string ShotGuidance::Text() const {
  std::string text = shot + ": ";
  text += flash_cam ? Format("flash %s", flash_words.c_str()) : "flash position unknown";
  text += Format(" (guidance in %.2f s)", seconds);
  if (!rig_news.empty()) text += "\n  located: " + rig_news;
  if (coverage) text += "\n" + Indented(CoverageSummary(*coverage) + "\n" + NextShotLines(*coverage));
  for (const std::string& w : warnings) text += "\n  warning: " + w;
  for (const std::string& m : missing) text += "\n  missing: " + m;
  return text;
}

}  // namespace mesocap::app

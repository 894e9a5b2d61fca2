// mesocap demo: the virtual rig through every stage that works so far, results and a report in
// one folder. Each stage adds itself here, so the README's first command shows everything.
#include "app/demo_args.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app/commands.h"
#include "app/demo_console.h"
#include "app/demo_reconstruct.h"
#include "app/process.h"
#include "app/demo_synthesis.h"
#include "mesh/mesh_shapes.h"
#include "app/session_stages.h"
#include "app/stage_clock.h"
#include "calib/calibrate.h"
#include "calib/resample.h"
#include "calib/truth_comparison.h"
#include "capture/btf_render.h"
#include "capture/simulate.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "core/image_u8_io.h"
#include "core/parallel.h"
#include "core/session.h"
#include "export/previews.h"
#include "export/report.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;

// The photo at no less than `width` pixels across: a JPEG decoded at 1/2 to 1/8 of its size by
// libjpeg's scaled inverse DCT (a 6 MP shot in a few ms), anything else read whole.
StatusOr<Image> ReadPreview(const fs::path& file, int width) {
  auto jpeg = JpegRowReader::Open(file, 3, width);
  if (!jpeg.ok()) return jpeg.status();
  if (!*jpeg) return ReadImage(file, {.linearize = false});
  auto image = (*jpeg)->ReadAll();
  if (!image.ok()) return image.status();
  return ImageU8ToFloat(*image);
}

// Thumbnails of every few of `files`, decoded in parallel (full-size photos: seconds each).
Status ContactSheetOf(const fs::path& session, const std::vector<std::string>& files, const fs::path& out_file,
                      int max_images) {
  std::vector<std::string> chosen;
  const int step = std::max(1, int(files.size()) / max_images);
  for (size_t k = 0; k < files.size() && int(chosen.size()) < max_images; k += step) chosen.push_back(files[k]);
  std::vector<Image> images(chosen.size());
  std::vector<std::string> labels(chosen.size()), errors(chosen.size());
  ParallelFor(0, int(chosen.size()), [&](int k) {
    auto im = ReadPreview(session / chosen[k], 240);
    if (!im.ok()) {
      errors[k] = im.status().message();
      return;
    }
    images[k] = Thumbnail(*im, 240);
    labels[k] = fs::path(chosen[k]).filename().string();
  });
  for (const std::string& error : errors)
    if (!error.empty()) return Status::Error(error);
  return WriteImage(out_file, ContactSheet(images, labels, 6, 240), {.format = PixelFormat::kUint8Srgb});
}

// Where the time went, against the demo's budget of one minute on 2 cores.
void AddTiming(const StageClock& clock, Report* report) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& [stage, seconds] : clock.stages()) rows.push_back({stage, Format("%.1f", seconds)});
  const double total = clock.TotalSeconds();
  rows.push_back({"total (wall clock)", Format("%.1f", total)});
  report->Heading("Timing");
  report->Paragraph(Format("The whole demo took %.0f s of wall clock on %d threads (budget: 60 s on 2 cores). The capture "
                           "console ran alongside the stages from the contact sheets on; the last row is the wait for it.",
                           total, EffectiveThreadCount(-1)));
  report->Table({"stage", "seconds"}, rows);
}

// Calibration from session/calibration/ against truth.json.
Status AddCalibrationScores(const fs::path& session_dir, const Json& truth, const std::vector<StageOutcome>& outcomes,
                            Report* report) {
  auto cal = LoadSessionCalibration(session_dir);
  if (!cal.ok()) return cal.status();
  auto calibration_report = ReadJsonFile(SessionLayout(session_dir).calibration().report());
  if (!calibration_report.ok()) return calibration_report.status();
  const CalibrationScore score = ScoreAgainstTruth(*cal, truth);
  const Json& intrinsics = (*calibration_report)["intrinsics"];
  const std::string intrinsics_rms =
      intrinsics.contains("report") ? Format("RMS %.3f px", intrinsics["report"]["rms_reprojection_px"].get<double>()) : "given";
  report->Heading("Calibration against ground truth");
  report->Paragraph("The calibrate stage estimated the intrinsics from the checkerboard shots (" + intrinsics_rms +
                    "), then every board pose from its AprilTags, the balls from their outlines, the flash of every "
                    "shot from the balls' mirror highlights and its power from the grey cards. Errors against " +
                    SessionLayout("").truth().string() + ":");
  report->Table({"quantity", "error", "target"},
                {{"focal length fx / fy", Format("%.3f%% / %.3f%%", score.fx_error_pct, score.fy_error_pct), "< 0.3%"},
                 {"board rotation (max)", Format("%.3f deg (%d/%d boards)", score.board_rotation_max_deg, score.boards_posed, score.boards_total), "< 0.3 deg"},
                 {"board translation (max)", Format("%.3f mm", score.board_translation_max_mm), "< 1 mm"},
                 {"ball centre (max)", Format("%.2f mm (%d/%d balls)", score.ball_centre_max_mm, score.balls_found, score.balls_total), "< 2 mm"},
                 {"flash direction from the top board", Format("median %.3f, max %.3f deg (%d/%d shots)", score.light_direction_median_deg, score.light_direction_max_deg, score.shots_with_light, score.shots_total), "median < 0.5, max < 2 deg"},
                 {"flash distance (median)", Format("%.2f%%", score.light_distance_median_pct), "< 2%"},
                 {"flash power (median)", Format("%.2f%% (%d shots)", score.power_median_pct, score.power_shots), "< 3%"}});
  std::string rejected;
  for (const StageOutcome& o : outcomes)
    if (o.name == "calibrate")
      for (const std::string& r : o.summary.warnings) rejected += (rejected.empty() ? "" : "; ") + r;
  if (!rejected.empty()) report->Paragraph("Rejected or flagged: " + rejected);
  // The demo's report sits beside the session folder.
  report->Picture(RelativePath(SessionLayout(session_dir).calibration().lights_plot(), session_dir.parent_path()),
                  "The flash directions as calibrated (compare with the true ones above)");
  std::printf("demo: calibration: %s\n", score.Brief().c_str());
  return Status::Ok();
}

// The top board's resampled slices next to the true BTF at their directions.
Status AddSliceScores(const fs::path& out, const fs::path& session_dir, const RigScene& scene, const Material& material,
                      Report* report) {
  auto index = ReadJsonFile(SessionLayout(session_dir).slices().index());
  if (!index.ok()) return index.status();
  const RigBoard& board = scene.boards.front();
  std::vector<Json> top_slices;
  for (const Json& e : (*index)["slices"])
    if (e["board"].get<int>() == board.id) top_slices.push_back(e);
  std::sort(top_slices.begin(), top_slices.end(),
            [](const Json& x, const Json& y) { return x["theta_i_deg"].get<double>() < y["theta_i_deg"].get<double>(); });
  std::vector<Image> pairs;
  std::vector<std::string> pair_labels;
  std::vector<std::vector<std::string>> rows;
  const size_t shown = std::min<size_t>(6, top_slices.size());
  int size = 0;
  for (size_t k = 0; k < shown; ++k) {
    const Json& r = top_slices[k * top_slices.size() / shown];
    auto slice = ReadImage(SessionLayout(session_dir).slices().root / r["file"].get<std::string>());
    if (!slice.ok()) return slice.status();
    size = slice->width();
    const double ti = r["theta_i_deg"], pi = r["phi_i_deg"], to = r["theta_o_deg"], po = r["phi_o_deg"];
    const Image truth = RenderTrueBtfSlice(material, {ti, pi, to, po, size, board.patch_m, board.material_offset_m});
    // Side by side under one exposure; scored at 64 texels, a scale the camera resolves.
    Image pair(2 * size, size, 3);
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x)
        for (int c = 0; c < 3; ++c) {
          pair.at(x, y, c) = slice->at(x, y, c);
          pair.at(size + x, y, c) = truth.at(x, y, c);
        }
    pairs.push_back(ExposeForDisplay(pair, 0.995));
    pair_labels.push_back(Format("i(%.0f,%.0f): slice | truth", ti, pi));
    const Image got64 = AreaDownsample(*slice, 64), truth64 = AreaDownsample(truth, 64);
    double sum_got = 0, sum_truth = 0, sq = 0;
    for (size_t i = 0; i < got64.size(); ++i) {
      sum_got += got64.data()[i];
      sum_truth += truth64.data()[i];
      sq += std::pow(double(got64.data()[i]) - truth64.data()[i], 2);
    }
    rows.push_back({fs::path(r["shot"].get<std::string>()).filename().string(), Format("%.1f", ti), Format("%.0f", pi),
                    Format("%+.2f%%", 100 * (sum_got / sum_truth - 1)),
                    Format("%.2f%%", 100 * std::sqrt(sq / got64.size()) / (sum_truth / truth64.size())),
                    Format("%.3f", r["scale"].get<double>())});
  }
  report->Heading("BTF slices against the true BTF");
  report->Paragraph(Format("The resample stage turned every lit patch into a %dx%d slice normalised by the flash irradiance "
                           "(%zu slices, %zu skipped with their reasons in %s). Top-board slices "
                           "against the true BTF at the same directions (directional light, orthographic view), compared "
                           "after both are area-averaged to 64x64 texels:",
                           size, size, (*index)["slices"].size(), (*index)["skipped"].size(),
                           RelativePath(SessionLayout(session_dir).slices().index(), out).c_str()));
  if (pairs.empty()) return Status::Ok();
  MESOCAP_RETURN_IF_ERROR(WriteImage(out / "slices_vs_truth.jpg", ContactSheet(pairs, pair_labels, 2, 400),
                                     {.format = PixelFormat::kUint8Srgb}));
  report->Table({"shot", "theta_i deg", "phi_i deg", "mean error", "relative RMS (64x64)", "BRDF smoothing scale"}, rows);
  report->Picture("slices_vs_truth.jpg", "Top board: resampled slice (left) and true BTF slice (right) of each pair, one exposure per pair");
  return Status::Ok();
}

}  // namespace

int RunDemo(DemoArgs& a) {
  if (!IsMissingOrEmptyDir(a.out))
    return Fail("demo", a.out.string() + ": exists and is not empty; choose a new folder", kExitUsage);
  a.simulate.out = a.out / "session";
  if (std::string why = a.simulate.Check(); !why.empty()) return Fail("demo", why, kExitUsage);
  std::fprintf(stderr, "demo: rendering the virtual rig (%d shots + %d checkerboard shots, %dx%d, %s)\n",
               a.simulate.rig.shots, a.simulate.rig.calib_shots, a.simulate.rig.width, a.simulate.rig.height,
               a.simulate.rig.material.c_str());
  StageClock clock;
  clock.Start("render the virtual session");
  ProgressBar bar("simulate", !a.no_progress);
  auto sim = SimulateSession(a.simulate, bar.AsCallback());
  if (!sim.ok()) return Fail("demo", sim.status());
  const fs::path session_dir = a.simulate.out;
  auto truth_json = ReadJsonFile(SessionLayout(session_dir).truth());
  if (!truth_json.ok()) return Fail("demo", truth_json.status());
  auto scene = MakeRigScene(a.simulate.rig);
  auto material = Material::Create(a.simulate.rig.material);
  if (!scene.ok() || !material.ok()) return Fail("demo", "cannot rebuild the rig");

  Report report("mesocap demo: virtual capture of '" + a.simulate.rig.material + "'");
  report.Paragraph("The virtual rig rendered a complete capture session with known ground truth: " + sim->Brief() +
                   ". Every later stage is scored against this truth.");

  // The console records its own session on its own thread from here, in the cores the stages leave.
  auto console = StartConsoleRecording(a.out);

  // Shots.
  std::vector<std::string> shot_files, calib_files;
  for (const auto& s : scene->shots) shot_files.push_back(fs::path(s.file).replace_extension(ExtensionForFormat(a.simulate.image_format)).string());
  for (const auto& s : scene->calib_shots) calib_files.push_back(fs::path(s.file).replace_extension(ExtensionForFormat(a.simulate.image_format)).string());
  clock.Start("contact sheets");
  std::fprintf(stderr, "demo: contact sheets of the shots\n");
  if (Status st = ContactSheetOf(session_dir, shot_files, a.out / "contact_sheet.jpg", 24); !st.ok())
    return Fail("demo", st);
  report.Heading("Shots");
  report.Picture("contact_sheet.jpg", "Flash shots (every few): the pyramid of 13 boards, 4 billiard balls, 2 grey cards");
  if (!calib_files.empty()) {
    if (Status st = ContactSheetOf(session_dir, calib_files, a.out / "calibration_sheet.jpg", 12); !st.ok())
      return Fail("demo", st);
    report.Picture("calibration_sheet.jpg", "Checkerboard shots for camera calibration");
  }

  // Ground truth.
  report.Heading("Ground truth (" + RelativePath(SessionLayout(session_dir).truth(), a.out) + ")");
  const auto& K = scene->camera.K;
  const auto& d = scene->camera.dist;
  report.Table({"fx px", "fy px", "cx px", "cy px", "k1", "k2", "p1", "p2", "k3"},
               {{Format("%.1f", K(0, 0)), Format("%.1f", K(1, 1)), Format("%.1f", K(0, 2)), Format("%.1f", K(1, 2)),
                 Format("%.4f", d[0]), Format("%.4f", d[1]), Format("%.5f", d[2]), Format("%.5f", d[3]), Format("%.4f", d[4])}});
  std::vector<std::vector<std::string>> board_rows;
  for (const auto& b : scene->boards)
    board_rows.push_back({std::to_string(b.id), Format("%.1f", b.tilt_deg), Format("%.1f", b.view_incidence_deg),
                          Format("%.3f", b.t.z()), Format("%d-%d", b.tags.front().id, b.tags.back().id)});
  report.Table({"board", "tilt deg", "view incidence deg", "depth m", "tags"}, board_rows);

  // Flash positions seen from the top board.
  std::vector<Eigen::Vector3d> dirs;
  const RigBoard& top = scene->boards.front();
  for (const auto& s : scene->shots) dirs.push_back(top.R.transpose() * (s.light_m - top.t));
  if (Status st = WriteImage(a.out / "true_lights.png", HemispherePlot(dirs, 420, "flash directions, top board frame"),
                             {.format = PixelFormat::kUint8Srgb});
      !st.ok())
    return Fail("demo", st);
  report.Picture("true_lights.png", "Flash directions seen from the top board (centre: zenith, rings: 30/60/90 deg)");

  // True BTF slices for a few direction pairs.
  std::vector<Image> slices;
  std::vector<std::string> labels;
  for (auto [ti, pi, to, po] : {std::array<double, 4>{0, 0, 0, 0}, {45, 0, 0, 0}, {60, 90, 0, 0}, {30, 180, 30, 0},
                                {45, 45, 60, 225}, {75, 0, 60, 0}}) {
    TrueBtfRequest r{ti, pi, to, po, 256};
    slices.push_back(ExposeForDisplay(RenderTrueBtfSlice(*material, r), 0.995));
    labels.push_back(Format("i(%g,%g) o(%g,%g)", ti, pi, to, po));
  }
  if (Status st = WriteImage(a.out / "true_btf.jpg", ContactSheet(slices, labels, 6, 180), {.format = PixelFormat::kUint8Srgb});
      !st.ok())
    return Fail("demo", st);
  report.Picture("true_btf.jpg", "True BTF slices of the material (light and view (theta, phi) in degrees), each exposed to its own range");

  // The session through `mesocap process`, then every stage scored against the truth it never reads.
  std::fprintf(stderr, "demo: mesocap process %s\n", session_dir.string().c_str());
  ProcessOptions process;
  process.session = session_dir;
  process.progress = !a.no_progress;
  process.reconstruct.grid = "coarse";  // the demo scores the reconstruction itself, below
  // A sphere and a torus dressed in the reconstructed BTF by both methods (SESSION/decorate/), with a light sweep
  // in the session's report; small meshes, small atlases and 24 representative slices keep it short.
  const fs::path meshes = a.out / "meshes";
  fs::create_directories(meshes);
  for (const auto& [name, mesh] : {std::pair{"sphere.obj", IcoSphere(4)}, std::pair{"torus.obj", Torus(120, 40)}}) {
    if (Status st = WriteObj(meshes / name, mesh); !st.ok()) return Fail("demo", st);
    process.decorate.meshes.push_back(meshes / name);
  }
  process.decorate.methods = {"texton", "quilt"};
  process.decorate.representative_slices = 24;  // as the plane's texton synthesis below
  process.decorate.preview_size = 256;
  process.decorate.atlas_size = 256;  // the previews are 256 pixels: a 256 texel atlas shows all a quilt holds
  clock.Stop();
  auto outcomes = RunProcess(process);
  if (!outcomes.ok()) return Fail("demo", outcomes.status());
  for (const StageOutcome& o : *outcomes) clock.Add("process: " + o.name, o.seconds);
  if (Status st = WriteProcessReport(session_dir, *outcomes); !st.ok()) return Fail("demo", st);
  report.Heading("mesocap process");
  report.Paragraph("`mesocap process session` ran every stage (its own report: " +
                   RelativePath(SessionLayout(session_dir).report_html(), a.out) + "):");
  std::vector<std::vector<std::string>> stage_rows;
  for (const StageOutcome& o : *outcomes)
    stage_rows.push_back({o.name, Format("%.1f", o.seconds), o.summary.brief, std::to_string(o.summary.warnings.size())});
  report.Table({"stage", "seconds", "outputs", "warnings"}, stage_rows);

  clock.Start("scoring calibration and slices");
  if (Status st = AddCalibrationScores(session_dir, *truth_json, *outcomes, &report); !st.ok()) return Fail("demo", st);
  if (Status st = AddSliceScores(a.out, session_dir, *scene, *material, &report); !st.ok()) return Fail("demo", st);

  DemoReconstructionInputs rec;
  rec.out = a.out;
  rec.session = session_dir;
  rec.material = &*material;
  rec.top_board = scene->boards.front().id;
  rec.top_offset_m = scene->boards.front().material_offset_m;
  rec.patch_m = scene->boards.front().patch_m;
  rec.progress = !a.no_progress;
  rec.clock = &clock;
  if (Status st = AddReconstructionToDemo(rec, &report); !st.ok()) return Fail("demo", st);
  if (Status st = AddSynthesisToDemo(a.out, session_dir, rec.top_board, &clock, &report); !st.ok())
    return Fail("demo", st);
  clock.Start("waiting for the capture console");
  auto recording = console.get();
  if (!recording.ok()) return Fail("demo", recording.status());
  AddConsoleToReport(*recording, &report);

  clock.Stop();
  AddTiming(clock, &report);
  report.Heading("Files");
  const SessionLayout session(session_dir);
  const auto in_session = [&](const fs::path& p) { return session.Relative(p); };
  report.Paragraph(FolderName(session.root()) + ": the virtual session as `mesocap process` left it (its files are listed by `mesocap layout " +
                   RelativePath(session.root(), a.out) + "`): the shots, " + in_session(session.truth()) + ", " +
                   in_session(session.calibration().root) + "/ (calibration), " + in_session(session.slices().root) +
                   "/ (OpenEXR BTF slices), " + in_session(session.ptm().root) + "/ (a PTM per board), " +
                   in_session(session.btf().root) + "/ (the reconstructed BTF, coarse grid), " +
                   in_session(session.exports().root) + "/ (the exports) and its own report. Formats: docs/formats.md.");
  if (Status st = report.Write(a.out); !st.ok()) return Fail("demo", st);
  std::printf("demo: %s\n", sim->Brief().c_str());
  std::printf("demo: finished in %.0f s -> %s\n", clock.TotalSeconds(), (a.out / ReportHtmlName()).string().c_str());
  return kExitOk;
}
}  // namespace mesocap::app

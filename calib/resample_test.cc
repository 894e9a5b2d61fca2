// Patch resampling: the texel grid and the irradiance normalisation on an analytic flat
// Lambertian photo, the BRDF smoothing on synthetic means, and a rendered session calibrated
// and resampled, each slice scored against the virtual rig's true BTF (truth.json and the
// material are read by the test only).
#include "calib/resample.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "capture/btf_render.h"
#include "capture/rig_material.h"
#include "capture/simulate.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "core/parallel.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

namespace fs = std::filesystem;

double MeanOf(const Image& im) {
  double sum = 0;
  for (size_t i = 0; i < im.size(); ++i) sum += im.data()[i];
  return sum / im.size();
}

// sqrt(mean (a - b)^2) / mean(b) over every texel and channel.
double RelativeRms(const Image& a, const Image& b) {
  double sq = 0;
  for (size_t i = 0; i < a.size(); ++i) sq += (double(a.data()[i]) - b.data()[i]) * (double(a.data()[i]) - b.data()[i]);
  return std::sqrt(sq / a.size()) / MeanOf(b);
}

CameraModel TestCamera() {
  CameraModel c;
  c.width = 800;
  c.height = 600;
  c.K << 1000, 0, 401.3, 0, 1002, 297.8, 0, 0, 1;
  c.dist = {-0.08, 0.05, 0.0004, -0.0003, -0.01};
  return c;
}

BoardPose TiltedBoard() {
  BoardPose pose;
  pose.id = 3;
  pose.found = true;
  pose.R = (Eigen::AngleAxisd(DegToRad(35), Eigen::Vector3d(0.6, 0.8, 0)) *
            Eigen::AngleAxisd(DegToRad(180), Eigen::Vector3d::UnitX()))  // board z toward the camera
               .toRotationMatrix();
  pose.t = {0.02, -0.015, 0.5};
  return pose;
}

TEST(Resample, TexelGridIsTheTrueBtfGrid) {
  const CameraModel camera = TestCamera();
  const BoardPose pose = TiltedBoard();
  const PatchSampler s = MakePatchSampler(camera, pose, 0.064, 32, 1);
  ASSERT_EQ(s.supersample, 1);
  for (auto [i, j] : {std::pair{0, 0}, {31, 0}, {0, 31}, {17, 5}}) {
    const Eigen::Vector2d xy = TexelCentre(i, j, 32, 0.064);
    const Eigen::Vector2d px = camera.Project(pose.R * Eigen::Vector3d(xy.x(), xy.y(), 0) + pose.t);
    const Eigen::Vector2f got = s.pixels[size_t(j) * 32 + i];
    EXPECT_NEAR(got.x(), px.x() + 0.5, 1e-3);  // Image::SampleBilinear's pixel centres are at +0.5
    EXPECT_NEAR(got.y(), px.y() + 0.5, 1e-3);
  }
  // A texel of 64 mm / 32 at 0.5 m with f = 1000 px spans ~4 px: area averaging takes over.
  EXPECT_GE(MakePatchSampler(camera, pose, 0.064, 32).supersample, 3);
}

TEST(Resample, ATexelsSizeInThePhotoIsItsProjectedArea) {
  // Head-on at 0.5 m on the optical axis (no distortion there): 2 mm texels span f 2 mm / 0.5 m,
  // about 4 px a side (fx 1000, fy 1002: the area's root).
  const CameraModel camera = TestCamera();
  BoardPose pose;
  pose.found = true;
  pose.R = Eigen::AngleAxisd(DegToRad(180), Eigen::Vector3d::UnitX()).toRotationMatrix();
  pose.t = {0, 0, 0.5};
  const double head_on = std::sqrt(1000.0 * 1002.0) * 0.002 / 0.5;
  EXPECT_NEAR(MakePatchSampler(camera, pose, 0.064, 32, 1).texel_px, head_on, 0.01 * head_on);
  // Tilted 60 deg about x: foreshortened to half along y, so its area's root falls by sqrt(1/2).
  pose.R = pose.R * Eigen::AngleAxisd(DegToRad(60), Eigen::Vector3d::UnitX()).toRotationMatrix();
  EXPECT_NEAR(MakePatchSampler(camera, pose, 0.064, 32, 1).texel_px, head_on * std::sqrt(0.5), 0.02 * head_on);
}

// A flat Lambertian board under a point flash, rendered analytically: the slice must read
// albedo/pi cos(theta_i) with each texel's own light direction (the cosine is part of the BTF).
TEST(Resample, FlatLambertianUnderPointFlashReadsAlbedoOverPiCos) {
  const CameraModel camera = TestCamera();
  const BoardPose pose = TiltedBoard();
  const double albedo = 0.6, power = 1.3, exposure = 0.4, patch = 0.064;
  const Eigen::Vector3d light_m = pose.R * Eigen::Vector3d(0.15, -0.25, 0.3) + pose.t;
  Image photo(camera.width, camera.height, 3);
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const Eigen::Vector3d d = camera.PixelToRay({double(x), double(y)});
      const Eigen::Vector3d n = pose.R.col(2);
      const double s = n.dot(pose.t) / n.dot(d);
      const Eigen::Vector3d p = s * d;
      const Eigen::Vector3d to_light = light_m - p;
      const double v = exposure * albedo / std::numbers::pi * power * std::max(0.0, n.dot(to_light.normalized())) /
                       to_light.squaredNorm();
      for (int c = 0; c < 3; ++c) photo.at(x, y, c) = float(v);
    }
  const Eigen::Vector3d light_in_board = pose.R.transpose() * (light_m - pose.t);
  for (int size : {64, 256}) {
    const PatchSampler sampler = MakePatchSampler(camera, pose, patch, size);
    int saturated = -1;
    const Image slice = ResamplePatch(photo, sampler, light_in_board, power * exposure, 0.99, &saturated);
    EXPECT_EQ(saturated, 0);
    double worst = 0;
    for (int j = 0; j < size; ++j)
      for (int i = 0; i < size; ++i) {
        const Eigen::Vector2d xy = TexelCentre(i, j, size, patch);
        const double cos_i = (light_in_board - Eigen::Vector3d(xy.x(), xy.y(), 0)).normalized().z();
        const double expected = albedo / std::numbers::pi * cos_i;
        worst = std::max(worst, std::abs(slice.at(i, j, 1) / expected - 1));
      }
    EXPECT_LT(worst, 0.003) << "size " << size;
  }
}

TEST(Resample, BrdfSmoothingAbsorbsAPowerError) {
  // A Lambertian view sampled every ~3 deg; one shot's power overestimated by 10%.
  std::vector<double> mean;
  std::vector<Eigen::Vector3d> light;
  for (int a = 0; a < 12; ++a)
    for (int b = 0; b < 12; ++b) {
      light.push_back(DirectionFromAnglesDeg(20 + 3 * a, 40 + 4 * b));
      mean.push_back(0.2 * light.back().z());
    }
  const int odd = 5 * 12 + 6;
  mean[odd] /= 1.1;
  const std::vector<double> scale = BrdfSmoothingScales(mean, light, 5.0);
  EXPECT_NEAR(mean[odd] * scale[odd] / (0.2 * light[odd].z()), 1.0, 0.03);
  EXPECT_NEAR(scale[0], 1.0, 0.01);  // far from the odd one: a smooth BRDF is left alone
}

// Truth of what the photo holds at one texel: the rig's point flash and perspective view, so
// the light and view directions vary over the patch; normalised like the resampler does (by
// power / d^2 to the texel's reference-plane point).
Image PointLightTruth(const Material& material, const RigBoard& board, const Eigen::Vector3d& light_m, int size,
                      int num_threads) {
  const Eigen::Vector3d light_in_board = board.R.transpose() * (light_m - board.t);
  const Eigen::Vector3d camera_in_board = -board.R.transpose() * board.t;
  const Eigen::Vector3d offset(board.material_offset_m.x(), board.material_offset_m.y(), 0);
  Image out(size, size, 3);
  ParallelFor(0, size, [&](int j) {
    for (int i = 0; i < size; ++i) {
      const Eigen::Vector2d xy = TexelCentre(i, j, size, board.patch_m);
      const Eigen::Vector3d p0(xy.x(), xy.y(), 0);
      const Eigen::Vector3d wo = (camera_in_board - p0).normalized();
      const MaterialHit hit = TraceFromViewer(material, xy.x() + offset.x(), xy.y() + offset.y(), wo);
      const Eigen::Vector3d to_light = light_in_board - (hit.point - offset);
      const Eigen::Vector3d wi = to_light.normalized();
      if (SelfShadowed(material, hit.point, wi)) continue;
      const double irradiance_ratio = (light_in_board - p0).squaredNorm() / to_light.squaredNorm();
      const Eigen::Vector3f L = ReflectedRadiance(material, hit, wi, wo) * float(irradiance_ratio);
      for (int c = 0; c < 3; ++c) out.at(i, j, c) = L[c];
    }
  }, num_threads);
  return out;
}

struct Scores {
  double mean_error = 0;       // mean(resampled) / mean(truth) - 1
  double rel_rms_64 = 0, rel_rms_128 = 0, rel_rms_512 = 0;
  double direction_mean_error = 0, direction_rel_rms_64 = 0;  // point-light truth vs directional truth
  double resampling_rel_rms_64 = 0;                           // resampled vs point-light truth
};

// The acceptance test of issue 4, step 6. The camera resolves the 64 mm top patch with ~230 px,
// so a 512-texel slice is ~2.2 texels a pixel: slices and truth are compared after both are
// box-filtered (area-averaged) to 64 texels a side (~3.6 px a texel), a resolution the camera
// resolves; the figures at 128 and at the full 512 are printed too. Two more columns split the
// error: "dir" is the point-lit, perspective truth (what the photo holds) against the
// directional, orthographic truth (what a slice claims): the systematic error of one direction
// per patch; "resampling" is the slice against that point-lit truth (camera blur, sensor noise,
// JPEG, calibration error).
TEST(Resample, RenderedSessionMatchesTrueBtf) {
  const auto dir = testing::MakeTempDir();
  SimulateOptions sim;
  sim.rig.material = "weave";
  sim.rig.seed = 21;
  sim.rig.shots = 8;
  sim.rig.calib_shots = 0;
  sim.out = dir / "session";
  ASSERT_TRUE(SimulateSession(sim).ok());
  auto scene = MakeRigScene(sim.rig);
  ASSERT_TRUE(scene.ok());
  auto material = Material::Create(sim.rig.material);
  ASSERT_TRUE(material.ok());

  CalibrateOptions co;
  co.session = sim.out;
  // The true intrinsics, as calib/calibrate_test: calib/intrinsics_test scores the intrinsics.
  auto cal = CalibrateSession(co, LayoutOf(*scene), scene->camera);
  ASSERT_TRUE(cal.ok()) << cal.status().message();
  std::printf("calibrate: %s\n", cal->Brief().c_str());

  ResampleOptions ro;  // defaults: 512 texels, BRDF smoothing on
  auto res = ResampleSession(ro, sim.out, LayoutOf(*scene), *cal);
  ASSERT_TRUE(res.ok()) << res.status().message();
  std::printf("resample: %s\n", res->Brief().c_str());
  for (const auto& s : res->skipped) std::printf("  skipped board %d %s: %s\n", s.board, s.shot.c_str(), s.reason.c_str());
  auto index = ReadJsonFile(sim.out / "slices" / "index.json");
  ASSERT_TRUE(index.ok());
  EXPECT_EQ(index->at("slices").size(), res->slices.size());
  EXPECT_EQ(index->at("skipped").size(), res->skipped.size());

  std::map<std::string, int> shot_of_file;
  for (size_t k = 0; k < scene->shots.size(); ++k)
    shot_of_file[fs::path(scene->shots[k].file).replace_extension(".jpg").string()] = int(k);
  std::map<int, std::vector<Scores>> per_board;
  int top_slices = 0;
  std::printf("board shot      theta_i phi_i theta_o spread | mean err  rms@64  rms@128 rms@512 | dir: mean  rms@64 | resampling rms@64 | scale\n");
  std::map<int, int> scored;
  for (const SliceRecord& r : res->slices) {
    if (r.board != 0 && ++scored[r.board] > 3) continue;  // three per tilted board keep the test short
    ImageInfo info;
    auto slice = ReadImage(sim.out / "slices" / r.file, {}, &info);
    ASSERT_TRUE(slice.ok()) << slice.status().message();
    ASSERT_EQ(slice->width(), 512);
    ASSERT_TRUE(info.attributes.count("mesocap:theta_i_deg")) << r.file;
    EXPECT_NEAR(std::get<float>(info.attributes.at("mesocap:theta_i_deg")), r.theta_i_deg, 1e-3);
    const RigBoard& board = scene->boards.at(r.board);
    const bool top = r.board == 0;
    // Truth at full resolution for the top board; at 256 (enough for the 64-texel comparison)
    // for the tilted ones, to keep the test short.
    const int truth_size = top ? 512 : 256;
    TrueBtfRequest req{r.theta_i_deg, r.phi_i_deg, r.theta_o_deg, r.phi_o_deg, truth_size, board.patch_m,
                       board.material_offset_m};
    const Image truth = RenderTrueBtfSlice(*material, req);
    const Image point = PointLightTruth(*material, board, scene->shots.at(shot_of_file.at(r.shot)).light_m, truth_size, -1);
    Scores s;
    s.mean_error = MeanOf(*slice) / MeanOf(truth) - 1;
    const Image got64 = AreaDownsample(*slice, 64), truth64 = AreaDownsample(truth, 64), point64 = AreaDownsample(point, 64);
    s.rel_rms_64 = RelativeRms(got64, truth64);
    s.rel_rms_128 = RelativeRms(AreaDownsample(*slice, 128), AreaDownsample(truth, 128));
    s.rel_rms_512 = top ? RelativeRms(*slice, truth) : NAN;
    s.direction_mean_error = MeanOf(point) / MeanOf(truth) - 1;
    s.direction_rel_rms_64 = RelativeRms(point64, truth64);
    s.resampling_rel_rms_64 = RelativeRms(got64, point64);
    per_board[r.board].push_back(s);
    std::printf("%5d %s %7.1f %5.0f %7.1f %6.2f | %+7.2f%% %6.2f%% %6.2f%% %6.2f%% | %+6.2f%% %6.2f%% | %6.2f%% | %.3f\n",
                r.board, fs::path(r.shot).filename().c_str(), r.theta_i_deg, r.phi_i_deg, r.theta_o_deg,
                r.light_spread_deg, 100 * s.mean_error, 100 * s.rel_rms_64, 100 * s.rel_rms_128, 100 * s.rel_rms_512,
                100 * s.direction_mean_error, 100 * s.direction_rel_rms_64, 100 * s.resampling_rel_rms_64, r.scale);
    if (top) {
      ++top_slices;
      EXPECT_LT(std::abs(s.mean_error), 0.03) << r.file;
      EXPECT_LT(s.rel_rms_64, 0.10) << r.file;
    }
  }
  std::printf("per board (max |mean err|, max rms@64, median rms@64, max direction-only rms@64, max resampling-only rms@64):\n");
  for (auto& [b, v] : per_board) {
    double max_mean = 0, max_rms = 0, max_dir = 0, max_res = 0;
    std::vector<double> rms;
    for (const Scores& s : v) {
      max_mean = std::max(max_mean, std::abs(s.mean_error));
      max_rms = std::max(max_rms, s.rel_rms_64);
      max_dir = std::max(max_dir, s.direction_rel_rms_64);
      max_res = std::max(max_res, s.resampling_rel_rms_64);
      rms.push_back(s.rel_rms_64);
    }
    std::nth_element(rms.begin(), rms.begin() + rms.size() / 2, rms.end());
    std::printf("  board %2d (%zu slices, view %.0f deg): %.2f%%  %.2f%%  %.2f%%  %.2f%%  %.2f%%\n", b, v.size(),
                scene->boards[b].view_incidence_deg, 100 * max_mean, 100 * max_rms, 100 * rms[rms.size() / 2],
                100 * max_dir, 100 * max_res);
  }
  EXPECT_GE(top_slices, int(sim.rig.shots) - 2);
}

}  // namespace
}  // namespace mesocap

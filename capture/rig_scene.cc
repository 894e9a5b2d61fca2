#include "capture/rig_scene.h"

#include <Eigen/Geometry>

#include <cmath>
#include <random>

#include "capture/rig_material.h"
#include "core/directions.h"
#include "core/session_layout.h"

namespace mesocap {
namespace {

constexpr double kCameraHeight_m = 1.0;
constexpr double kTagSize_m = 0.022;
constexpr double kTagMargin_m = 0.0028;  // >= one cell of white quiet zone

Eigen::Matrix3d SmallRotation(std::mt19937_64& rng, double max_deg) {
  std::uniform_real_distribution<double> u(-1, 1);
  const Eigen::Vector3d axis = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
  return Eigen::AngleAxisd(DegToRad(max_deg * u(rng)), axis).toRotationMatrix();
}

// Four tags in the board's corners, upright in the board frame (x right, y up seen from +z).
std::vector<RigTag> CornerTags(int first_id, double board_size_m, double tag_size_m = kTagSize_m) {
  std::vector<RigTag> tags;
  const double c = board_size_m / 2 - kTagMargin_m - tag_size_m / 2;
  const Eigen::Vector2d centres[4] = {{-c, c}, {c, c}, {c, -c}, {-c, -c}};
  for (int k = 0; k < 4; ++k) {
    RigTag tag;
    tag.id = first_id + k;
    tag.size_m = tag_size_m;
    tag.centre_m = centres[k];
    const double h = tag_size_m / 2;
    tag.corners_m = {centres[k] + Eigen::Vector2d(-h, -h), centres[k] + Eigen::Vector2d(h, -h),
                     centres[k] + Eigen::Vector2d(h, h), centres[k] + Eigen::Vector2d(-h, h)};
    tags.push_back(tag);
  }
  return tags;
}

}  // namespace

std::string RigOptions::Check() const {
  if (!Material::Create(material).ok()) return Material::Create(material).status().message();
  if (shots < 1 || shots > 5000) return "--shots must be between 1 and 5000";
  if (calib_shots < 0 || calib_shots > 200) return "--calib-shots must be between 0 and 200";
  if (width < 640 || height < 400 || width > 12000 || height > 8000)
    return "--width/--height must be within 640x400 .. 12000x8000";
  const double aspect = double(width) / height;
  if (aspect < 1.2 || aspect > 2.0) return "--width/--height: aspect ratio must be within 1.2 .. 2.0 (the rig is framed for 3:2)";
  return "";
}

Json RigOptions::ToJson() const {
  return {{"material", material}, {"shots", shots}, {"calib_shots", calib_shots},
          {"seed", seed}, {"width", width}, {"height", height}};
}

StatusOr<RigScene> MakeRigScene(const RigOptions& options) {
  if (const std::string why = options.Check(); !why.empty()) return Status::Error(why);
  std::mt19937_64 rng(options.seed * 0x9E3779B97F4A7C15ull + 17);
  std::uniform_real_distribution<double> u01(0, 1), u11(-1, 1);
  RigScene s;
  s.options = options;

  // Camera: focal length scales with the width so any resolution frames the same rig.
  const double f = 1.2 * options.width * (1 + 0.01 * u11(rng));
  s.camera.width = options.width;
  s.camera.height = options.height;
  s.camera.K << f, 0, options.width / 2.0 - 0.5 + 0.01 * options.width * u11(rng), 0,
      f * (1 + 0.002 * u11(rng)), options.height / 2.0 - 0.5 + 0.01 * options.height * u11(rng), 0, 0, 1;
  s.camera.dist = {-0.08 + 0.01 * u11(rng), 0.06 + 0.01 * u11(rng), 0.0006 * u11(rng),
                   0.0006 * u11(rng), -0.01};

  // Camera looking straight down at the table with a small tilt; image up = world +y.
  Eigen::Matrix3d axes;
  axes.row(0) = Eigen::Vector3d(1, 0, 0);
  axes.row(1) = Eigen::Vector3d(0, -1, 0);
  axes.row(2) = Eigen::Vector3d(0, 0, -1);
  s.cam_from_world_R = axes * SmallRotation(rng, 1.5);
  const Eigen::Vector3d camera_centre_w(0.005 * u11(rng), 0.005 * u11(rng), kCameraHeight_m);
  s.cam_from_world_t = -s.cam_from_world_R * camera_centre_w;
  auto to_cam = [&](const Eigen::Vector3d& p_w) -> Eigen::Vector3d {
    return s.cam_from_world_R * p_w + s.cam_from_world_t;
  };

  // The pyramid: top board, 4 at ~30 deg and 8 at ~60 deg view incidence, tilted outward.
  struct Slot { double radius_m, azimuth_deg, height_m, incidence_deg; };
  std::vector<Slot> slots = {{0, 0, 0.09, 0}};
  for (int k = 0; k < 4; ++k) slots.push_back({0.125, 90.0 * k, 0.06, 30});
  for (int k = 0; k < 8; ++k) slots.push_back({k % 2 ? 0.215 : 0.22, 45.0 * k, 0.055, 60});
  for (size_t b = 0; b < slots.size(); ++b) {
    const Slot& slot = slots[b];
    RigBoard board;
    board.id = int(b);
    const double az = DegToRad(slot.azimuth_deg + 2 * u11(rng));
    const Eigen::Vector3d radial(std::cos(az), std::sin(az), 0);
    const Eigen::Vector3d centre_w = radial * slot.radius_m + Eigen::Vector3d(0, 0, slot.height_m);
    const double camera_offset_deg = RadToDeg(std::atan2(slot.radius_m, kCameraHeight_m - slot.height_m));
    const double tilt_deg = slot.incidence_deg == 0 ? 0 : slot.incidence_deg - camera_offset_deg + 2 * u11(rng);
    const double tilt = DegToRad(tilt_deg);
    const Eigen::Vector3d n = std::sin(tilt) * radial + std::cos(tilt) * Eigen::Vector3d::UnitZ();
    // Every patch is glued with the material's x along the world x (projected into the board):
    // the views then meet the material from different azimuths in its own frame, the rings of
    // Ngan & Durand's Fig. 5, instead of all from the same side.
    Eigen::Vector3d x_axis = (Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitX().dot(n) * n).normalized();
    if (slot.radius_m == 0) x_axis = Eigen::AngleAxisd(DegToRad(3 * u11(rng)), Eigen::Vector3d::UnitZ()) * Eigen::Vector3d::UnitX();
    const Eigen::Vector3d y_axis = n.cross(x_axis).normalized();
    Eigen::Matrix3d world_from_board;
    world_from_board << x_axis, y_axis, n;
    board.R = s.cam_from_world_R * world_from_board;
    board.t = to_cam(centre_w);
    board.tilt_deg = tilt_deg;
    board.view_incidence_deg = AngleBetweenDeg(board.R.col(2), -board.t);
    board.material_offset_m = {std::fmod(b * 0.0371, 0.096), std::fmod(b * 0.0529, 0.096)};
    board.tags = CornerTags(4 * int(b), board.size_m);
    s.boards.push_back(board);
  }

  // Billiard balls on the table at the sides, grey cards between them.
  const Eigen::Vector3d ball_colours[4] = {{0.80, 0.58, 0.04}, {0.04, 0.10, 0.50}, {0.60, 0.05, 0.04}, {0.04, 0.35, 0.10}};
  const Eigen::Vector2d ball_xy[4] = {{-0.31, 0.14}, {0.31, 0.14}, {0.31, -0.14}, {-0.31, -0.14}};
  for (int k = 0; k < 4; ++k) {
    RigSphere sphere;
    const Eigen::Vector3d c_w(ball_xy[k].x() + 0.008 * u11(rng), ball_xy[k].y() + 0.008 * u11(rng), sphere.radius_m);
    sphere.center_m = to_cam(c_w);
    sphere.base_rgb = ball_colours[k];
    s.spheres.push_back(sphere);
  }
  for (int k = 0; k < 2; ++k) {
    RigGreyCard card;
    const Eigen::Matrix3d world_from_card =
        Eigen::AngleAxisd(DegToRad(10 * u11(rng)), Eigen::Vector3d::UnitZ()).toRotationMatrix() *
        Eigen::AngleAxisd(DegToRad(4 * u11(rng)), Eigen::Vector3d::UnitX()).toRotationMatrix();
    card.R = s.cam_from_world_R * world_from_card;
    card.t = to_cam(Eigen::Vector3d((k ? 0.31 : -0.31) + 0.005 * u11(rng), 0.005 * u11(rng), 0.004));
    card.tags = CornerTags(4 * int(s.boards.size()) + 4 * k, card.size_m, 0.018);
    s.grey_cards.push_back(card);
  }

  // Flash: stratified over the upper hemisphere (elevation 15..80 deg), 0.5..1.5 m from the
  // target, power +-15% per shot.
  const Eigen::Vector3d target_w(0, 0, 0.06);
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  const double s_lo = std::sin(DegToRad(15)), s_hi = std::sin(DegToRad(80));
  for (int k = 0; k < options.shots; ++k) {
    const double frac = (k + u01(rng)) / options.shots;
    const double elevation = std::asin(s_lo + (s_hi - s_lo) * frac);
    const double azimuth = golden * k + 0.3 * u11(rng);
    const double distance = 0.5 + u01(rng);
    const Eigen::Vector3d dir(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
                              std::sin(elevation));
    RigShot shot;
    shot.light_m = to_cam(target_w + distance * dir);
    shot.power = 1.0 + 0.15 * u11(rng);
    shot.file = SessionLayout::ShotEntry("shot", k + 1, ".jpg");
    s.shots.push_back(shot);
  }

  // Checkerboard poses: 0.55..0.9 m away, tilted up to 40 deg, fully inside the frame.
  const RigCheckerboard& cb = s.checkerboard;
  const double w = (cb.cols + 1) * cb.square_m, h = (cb.rows + 1) * cb.square_m;
  for (int k = 0; k < options.calib_shots; ++k) {
    RigCalibShot cs;
    for (int attempt = 0; attempt < 1000; ++attempt) {
      const double tilt = DegToRad(15 + 25 * u01(rng)) * (attempt < 500 ? 1.0 : 0.5);
      const double dir = 2 * std::numbers::pi * u01(rng);
      const Eigen::Matrix3d R = Eigen::AngleAxisd(tilt, Eigen::Vector3d(std::cos(dir), std::sin(dir), 0)).toRotationMatrix() *
                                Eigen::AngleAxisd(DegToRad(15 * u11(rng)), Eigen::Vector3d::UnitZ()).toRotationMatrix();
      const double depth = 0.55 + 0.35 * u01(rng);
      const Eigen::Vector3d centre(0.12 * u11(rng) * depth, 0.08 * u11(rng) * depth, depth);
      // Board frame origin at the first inner corner; the pattern centre sits at `centre`.
      const Eigen::Vector3d t = centre - R * Eigen::Vector3d((cb.cols - 1) * cb.square_m / 2, (cb.rows - 1) * cb.square_m / 2, 0);
      bool inside = true;
      for (double cx : {-cb.square_m, w - cb.square_m})
        for (double cy : {-cb.square_m, h - cb.square_m}) {
          const Eigen::Vector3d p = R * Eigen::Vector3d(cx, cy, 0) + t;
          const Eigen::Vector2d px = s.camera.Project(p);
          const double m = 0.03 * options.width;
          inside = inside && p.z() > 0.3 && px.x() > m && px.y() > m && px.x() < options.width - m &&
                   px.y() < options.height - m;
        }
      if (inside) {
        cs.R = R;
        cs.t = t;
        break;
      }
    }
    cs.file = SessionLayout::ShotEntry("calib", k + 1, ".jpg");
    s.calib_shots.push_back(cs);
  }
  return s;
}

namespace {
Json PoseJson(const Eigen::Matrix3d& R, const Eigen::Vector3d& t) { return {{"R", ToJson(R)}, {"t", ToJson(t)}}; }
}  // namespace

Json TruthToJson(const RigScene& s) {
  Json j;
  j["format"] = "mesocap-truth";
  j["format_version"] = 1;
  j["options"] = s.options.ToJson();
  j["frame"] = "camera (OpenCV: x right, y down, z forward), metres";
  j["camera"] = s.camera.ToJson();
  j["world_from_note"] = "world = table frame, z up; X_cam = cam_from_world.R * X_world + cam_from_world.t";
  j["cam_from_world"] = PoseJson(s.cam_from_world_R, s.cam_from_world_t);
  j["table"] = {{"albedo", s.table_albedo}};
  j["boards"] = Json::array();
  for (const auto& b : s.boards) {
    Json jb = {{"id", b.id}, {"tilt_deg", b.tilt_deg}, {"view_incidence_deg", b.view_incidence_deg},
               {"size_m", b.size_m}, {"patch_m", b.patch_m}, {"material_offset_m", ToJson(b.material_offset_m)},
               {"R", ToJson(b.R)}, {"t", ToJson(b.t)}, {"albedo", s.board_albedo}, {"tags", Json::array()}};
    for (const auto& tag : b.tags) {
      Json corners = Json::array();
      for (const auto& c : tag.corners_m) corners.push_back(ToJson(c));
      jb["tags"].push_back({{"id", tag.id}, {"family", "tag36h11"}, {"size_m", tag.size_m},
                            {"centre_m", ToJson(tag.centre_m)}, {"corners_m", corners}});
    }
    j["boards"].push_back(jb);
  }
  j["spheres"] = Json::array();
  for (const auto& sp : s.spheres)
    j["spheres"].push_back({{"center_m", ToJson(sp.center_m)}, {"radius_m", sp.radius_m},
                            {"base_rgb", ToJson(sp.base_rgb)}, {"coat_f0", sp.coat_f0},
                            {"coat_roughness", sp.coat_roughness}});
  j["grey_cards"] = Json::array();
  for (const auto& c : s.grey_cards) {
    Json tags = Json::array();
    for (const auto& tag : c.tags) {
      Json corners = Json::array();
      for (const auto& corner : tag.corners_m) corners.push_back(ToJson(corner));
      tags.push_back({{"id", tag.id}, {"family", "tag36h11"}, {"size_m", tag.size_m}, {"centre_m", ToJson(tag.centre_m)},
                      {"corners_m", corners}});
    }
    j["grey_cards"].push_back({{"R", ToJson(c.R)}, {"t", ToJson(c.t)}, {"size_m", c.size_m}, {"patch_m", c.patch_m},
                               {"albedo", c.albedo}, {"tags", tags}});
  }
  j["flash"] = {{"model", "isotropic point light"},
                {"power_note", "irradiance at 1 m facing the flash; E = power * cos / d^2"}};
  j["exposure"] = s.exposure;
  j["shots"] = Json::array();
  for (const auto& sh : s.shots)
    j["shots"].push_back({{"file", sh.file}, {"light_m", ToJson(sh.light_m)}, {"power", sh.power}});
  j["checkerboard"] = {{"cols", s.checkerboard.cols}, {"rows", s.checkerboard.rows},
                       {"square_m", s.checkerboard.square_m}, {"margin_m", s.checkerboard.margin_m},
                       {"origin", "first inner corner; x along cols, y along rows"}};
  j["calib_shots"] = Json::array();
  for (const auto& c : s.calib_shots)
    j["calib_shots"].push_back({{"file", c.file}, {"R", ToJson(c.R)}, {"t", ToJson(c.t)}});
  j["material"] = {{"name", s.options.material}};
  j["sensor"] = {{"noise_shot", s.noise_shot}, {"noise_read", s.noise_read},
                 {"ambient_radiance_calib", s.ambient_radiance_calib}};
  return j;
}

RigLayout LayoutOf(const RigScene& s) {
  RigLayout l;
  for (const auto& b : s.boards) {
    LayoutBoard lb;
    lb.id = b.id;
    lb.size_m = b.size_m;
    lb.patch_m = b.patch_m;
    lb.nominal_incidence_deg = b.id == 0 ? 0 : b.id <= 4 ? 30 : 60;
    for (const auto& t : b.tags) lb.tags.push_back({t.id, t.size_m, t.corners_m});
    l.boards.push_back(lb);
  }
  l.sphere_count = int(s.spheres.size());
  l.sphere_radius_m = s.spheres.empty() ? 0 : s.spheres.front().radius_m;
  for (size_t k = 0; k < s.grey_cards.size(); ++k) {
    const RigGreyCard& c = s.grey_cards[k];
    LayoutBoard lc;
    lc.id = int(k);
    lc.size_m = c.size_m;
    lc.patch_m = c.patch_m;
    for (const auto& t : c.tags) lc.tags.push_back({t.id, t.size_m, t.corners_m});
    l.grey_cards.push_back(lc);
  }
  l.grey_card_albedo = s.grey_cards.empty() ? 0 : s.grey_cards.front().albedo;
  l.checker_cols = s.checkerboard.cols;
  l.checker_rows = s.checkerboard.rows;
  l.checker_square_m = s.checkerboard.square_m;
  return l;
}

StatusOr<RigScene> TruthFromJson(const Json& j) {
  try {
    RigOptions o;
    const Json& jo = j.at("options");
    o.material = jo.at("material");
    o.shots = jo.at("shots");
    o.calib_shots = jo.at("calib_shots");
    o.seed = jo.at("seed");
    o.width = jo.at("width");
    o.height = jo.at("height");
    // Regenerate the layout from the options, then check it matches what was stored.
    auto scene = MakeRigScene(o);
    if (!scene.ok()) return scene.status();
    if ((Matrix3dFromJson(j.at("camera").at("K")) - scene->camera.K).norm() > 1e-9)
      return Status::Error(SessionLayout("").truth().string() + " does not match the rig its options describe");
    return scene;
  } catch (const std::exception& e) {
    return Status::Error(SessionLayout("").truth().string() + ": " + e.what());
  }
}

}  // namespace mesocap

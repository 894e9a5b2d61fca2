#include "capture/rig_render.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/ggx.h"
#include "core/parallel.h"
#include "core/splitmix.h"

namespace mesocap {
namespace {

constexpr float kInvPi = float(1.0 / std::numbers::pi);

// The cone from `apex` that holds the sphere (centre, radius): unit axis and cosine of its half
// angle (-1 when the apex is inside). The sphere is enlarged a little, so rounding can never cull
// a point that the exact test would find.
struct Cone {
  Eigen::Vector3d axis;
  double cos_half_angle;
};
Cone ConeHolding(const Eigen::Vector3d& apex, const Eigen::Vector3d& centre, double radius) {
  radius = radius * 1.001 + 1e-6;
  const Eigen::Vector3d to_centre = centre - apex;
  const double distance = to_centre.norm();
  return {to_centre / std::max(distance, 1e-12),
          distance > radius ? std::sqrt(1 - (radius / distance) * (radius / distance)) : -1.0};
}

double IntersectSphere(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& c, double r) {
  const Eigen::Vector3d oc = o - c;
  const double b = oc.dot(d), cc = oc.squaredNorm() - r * r;
  const double disc = b * b - cc;
  if (disc < 0) return -1;
  const double sq = std::sqrt(disc);
  const double s0 = -b - sq;
  if (s0 > 1e-9) return s0;
  const double s1 = -b + sq;
  return s1 > 1e-9 ? s1 : -1;
}

double IntersectPlane(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& n,
                      const Eigen::Vector3d& p0) {
  const double den = n.dot(d);
  if (std::abs(den) < 1e-12) return -1;
  const double s = n.dot(p0 - o) / den;
  return s > 0 ? s : -1;
}


// Standard normal quantiles at 4096 equally likely levels: a table lookup per noise value
// instead of a log and a cosine (sensor noise needs the shape, not 53 bits of it).
const std::vector<float>& GaussianTable() {
  static const std::vector<float> table = [] {
    std::vector<float> t(4096);
    for (size_t i = 0; i < t.size(); ++i) {
      const double p = (i + 0.5) / t.size();
      // Inverse normal CDF by Newton on erfc, from a rational first guess.
      double x = std::sqrt(-2 * std::log(std::min(p, 1 - p)));
      x = x - (2.515517 + 0.802853 * x + 0.010328 * x * x) / (1 + 1.432788 * x + 0.189269 * x * x + 0.001308 * x * x * x);
      if (p < 0.5) x = -x;
      for (int it = 0; it < 4; ++it) {
        const double cdf = 0.5 * std::erfc(-x / std::sqrt(2.0));
        x -= (cdf - p) / (std::exp(-0.5 * x * x) / std::sqrt(2 * std::numbers::pi));
      }
      t[i] = float(x);
    }
    return t;
  }();
  return table;
}

// Counter-based: one hash of (the shot's key, index / 5) gives noise values index / 5 * 5 to
// + 4, 12 bits each; the values do not depend on the order they are drawn in.
constexpr int kNoiseValuesPerHash = 5;
uint64_t NoiseKey(uint64_t seed, uint64_t stream) { return SplitMix64(seed ^ SplitMix64(stream)); }

}  // namespace

std::string RigRenderOptions::Check() const {
  if (samples_per_axis < 1 || samples_per_axis > 8) return "samples per axis must be 1..8";
  if (patch_texels < 32 || patch_texels > 4096) return "patch texels must be 32..4096";
  return "";
}

int RigTruthSamplesPerAxis(int size, const RigRenderOptions& rig) { return std::max(2, rig.patch_texels / std::max(1, size)); }

RigRenderer::RigRenderer(const RigScene& scene, const Material& material, const RigRenderOptions& options)
    : scene_(scene), material_(material), options_(options) {
  int max_id = 0;
  for (const auto& b : scene_.boards)
    for (const auto& t : b.tags) max_id = std::max(max_id, t.id);
  for (const auto& c : scene_.grey_cards)
    for (const auto& t : c.tags) max_id = std::max(max_id, t.id);
  for (int id = 0; id <= max_id; ++id) tag_bitmaps_.push_back(Tag36h11Bitmap(id));
  auto add_square = [&](const Eigen::Matrix3d& R, const Eigen::Vector3d& t, double size) {
    const Cone cone = ConeHolding(Eigen::Vector3d::Zero(), t, size / 2 * std::sqrt(2.0));
    primary_squares_.push_back({SquareFrame::Of(R, t, size), cone.axis, cone.cos_half_angle});
  };
  for (const auto& board : scene_.boards) add_square(board.R, board.t, board.size_m);
  for (const auto& card : scene_.grey_cards) add_square(card.R, card.t, card.size_m);
  const int W = scene_.camera.width, H = scene_.camera.height;
  ray_grid_.resize(size_t(W + 1) * (H + 1));
  ParallelFor(0, H + 1, [&](int j) {
    for (int i = 0; i <= W; ++i) {
      const Eigen::Vector3d r = scene_.camera.PixelToRay({i - 0.5, j - 0.5});
      ray_grid_[size_t(j) * (W + 1) + i] = Eigen::Vector2f(float(r.x() / r.z()), float(r.y() / r.z()));
    }
  }, options_.num_threads);
}

Eigen::Vector3d RigRenderer::RayThrough(double x, double y) const {
  const Eigen::Vector2f xy = UndistortedAt(x, y);
  return Eigen::Vector3d(xy.x(), xy.y(), 1.0).normalized();
}

Eigen::Vector2f RigRenderer::UndistortedAt(double x, double y) const {
  const int W = scene_.camera.width, H = scene_.camera.height;
  const double gx = std::clamp(x + 0.5, 0.0, double(W)), gy = std::clamp(y + 0.5, 0.0, double(H));
  const int i = std::min(int(gx), W - 1), j = std::min(int(gy), H - 1);
  const float ax = float(gx - i), ay = float(gy - j);
  const Eigen::Vector2f* row0 = &ray_grid_[size_t(j) * (W + 1) + i];
  const Eigen::Vector2f* row1 = row0 + (W + 1);
  const Eigen::Vector2f top = row0[0] + (row0[1] - row0[0]) * ax;
  const Eigen::Vector2f bottom = row1[0] + (row1[1] - row1[0]) * ax;
  return top + (bottom - top) * ay;
}

std::vector<Eigen::Vector2d> RigRenderer::SubpixelOffsets() const {
  // Stratified, with distinct x and y per sample (n-rooks inside the grid).
  const int k = options_.samples_per_axis;
  std::vector<Eigen::Vector2d> offsets;
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < k; ++i) offsets.emplace_back((i + (j + 0.5) / k) / k, (j + (i + 0.5) / k) / k);
  return offsets;
}

RigRenderer::SquareFrame RigRenderer::SquareFrame::Of(const Eigen::Matrix3d& R, const Eigen::Vector3d& centre,
                                                      double size) {
  return {R.transpose(), R.transpose() * centre, size / 2};
}

// Distance along the camera ray d (unit) to the square, or -1: none is computed outside the
// square's cone.
double RigRenderer::IntersectPrimary(const PrimarySquare& primary, const Eigen::Vector3d& d) const {
  if (d.dot(primary.axis) < primary.cos_half_angle) return -1;
  const SquareFrame& square = primary.square;
  const Eigen::Vector3d ol = -square.origin, dl = square.to_local * d;
  if (std::abs(dl.z()) < 1e-12) return -1;
  const double s = -ol.z() / dl.z();
  if (s <= 0) return -1;
  return square.Covers(ol.x() + s * dl.x(), ol.y() + s * dl.y()) ? s : -1;
}

RigRenderer::Sample RigRenderer::TracePrimary(const Eigen::Vector3d& d) const {
  const Eigen::Vector3d o = Eigen::Vector3d::Zero();
  double best = 1e30;
  Kind kind = kNone;
  int index = 0;
  auto consider = [&](double s, Kind k, int i) {
    if (s > 0 && s < best) {
      best = s;
      kind = k;
      index = i;
    }
  };
  consider(IntersectPlane(o, d, scene_.TableNormalInCam(), scene_.TablePointInCam()), kTable, 0);
  // Boards, balls, then cards: on equal distances the first found is kept, as it always was.
  const size_t boards = scene_.boards.size();
  for (size_t b = 0; b < boards; ++b) consider(IntersectPrimary(primary_squares_[b], d), kBoard, int(b));
  for (size_t i = 0; i < scene_.spheres.size(); ++i)
    consider(IntersectSphere(o, d, scene_.spheres[i].center_m, scene_.spheres[i].radius_m), kSphere, int(i));
  for (size_t i = boards; i < primary_squares_.size(); ++i) consider(IntersectPrimary(primary_squares_[i], d), kCard, int(i - boards));
  const Eigen::Vector3d p = kind == kNone ? Eigen::Vector3d::Zero() : Eigen::Vector3d(best * d);
  return {float(p.x()), float(p.y()), float(p.z()), kind, uint8_t(index), kWhite};
}

void RigRenderer::Prepare(const ProgressFn& progress) {
  const int W = scene_.camera.width, H = scene_.camera.height;
  const auto offsets = SubpixelOffsets();
  const size_t spp = offsets.size();
  gbuffer_.assign(size_t(W) * H * spp, Sample{});
  ParallelFor(0, H, [&](int y) {
    for (int x = 0; x < W; ++x)
      for (size_t s = 0; s < spp; ++s) {
        const Eigen::Vector2d px(x - 0.5 + offsets[s].x(), y - 0.5 + offsets[s].y());
        Sample& sample = gbuffer_[(size_t(y) * W + x) * spp + s];
        sample = TracePrimary(RayThrough(px.x(), px.y()));
        sample.paint = PaintAt(sample);
      }
  }, options_.num_threads);
  ReportProgress(progress, 1, 2, "geometry buffer");

  // Each patch texel's view ray, traced into the height field once: the camera is fixed.
  const int N = options_.patch_texels;
  patch_texels_.assign(scene_.boards.size(), std::vector<PatchTexel>(size_t(N) * N));
  ParallelFor(0, int(scene_.boards.size()) * N, [&](int job) {
    const int b = job / N, j = job % N;
    const RigBoard& board = scene_.boards[b];
    const Eigen::Vector3d camera_in_board = -board.R.transpose() * board.t;
    for (int i = 0; i < N; ++i) {
      const Eigen::Vector2d uv = TexelCentre(i, j, N, board.patch_m);
      const Eigen::Vector3d wo = (camera_in_board - Eigen::Vector3d(uv.x(), uv.y(), 0)).normalized();
      const Eigen::Vector2d m = uv + board.material_offset_m;
      const MaterialHit hit = TraceFromViewer(material_, m.x(), m.y(), wo);
      PatchTexel& t = patch_texels_[b][size_t(j) * N + i];
      t.point_board = (hit.point - Eigen::Vector3d(board.material_offset_m.x(), board.material_offset_m.y(), 0)).cast<float>();
      t.normal = hit.normal;
      t.albedo = hit.albedo;
      t.wo = wo.cast<float>();
    }
  }, options_.num_threads);
  ReportProgress(progress, 2, 2, "patch view rays");
}

bool RigRenderer::Blocks(const ShadowCaster& caster, const Eigen::Vector3d& p, const Eigen::Vector3d& d,
                         double dist) const {
  if (caster.kind == kSphere) {
    const RigSphere& sphere = scene_.spheres[caster.index];
    const double s = IntersectSphere(p, d, sphere.center_m, sphere.radius_m);
    return s > 0 && s < dist;
  }
  // A square: p and the light on opposite sides of its plane (a cheap reject), and the segment
  // between them crossing the plane inside the square, further than 1 um from p.
  const Eigen::Vector3d q = caster.square.Local(p);
  const Eigen::Vector3d& l = caster.light_local;
  if ((q.z() > 0) == (l.z() > 0)) return false;
  const double u = q.z() / (q.z() - l.z());  // of the way from p to the light
  if (!(u * dist > 1e-6)) return false;
  return caster.square.Covers(q.x() + u * (l.x() - q.x()), q.y() + u * (l.y() - q.y()));
}

// The culled test gives the same answer; without a shot to share the casters, they are made here.
bool RigRenderer::Occluded(const Eigen::Vector3d& p, const Eigen::Vector3d& light, Kind self_kind,
                           int self_index) const {
  return Occluded(p, light, ShadowCastersFor(light), self_kind, self_index);
}

std::vector<RigRenderer::ShadowCaster> RigRenderer::ShadowCastersFor(const Eigen::Vector3d& light) const {
  std::vector<ShadowCaster> casters;
  auto add = [&](Kind kind, int index, const Eigen::Vector3d& centre, double radius) -> ShadowCaster& {
    const Cone cone = ConeHolding(light, centre, radius);
    ShadowCaster& c = casters.emplace_back();
    c.kind = kind, c.index = index, c.axis = cone.axis, c.cos_half_angle = cone.cos_half_angle;
    return c;
  };
  // A square's frame is set once per light: each test is then one rotation of p.
  auto add_square = [&](Kind kind, int index, const Eigen::Matrix3d& R, const Eigen::Vector3d& t, double size) {
    ShadowCaster& c = add(kind, index, t, size / 2 * std::sqrt(2.0));
    c.square = SquareFrame::Of(R, t, size);
    c.light_local = c.square.to_local * (light - t);
  };
  for (size_t i = 0; i < scene_.spheres.size(); ++i)
    add(kSphere, int(i), scene_.spheres[i].center_m, scene_.spheres[i].radius_m);
  for (size_t i = 0; i < scene_.grey_cards.size(); ++i)
    add_square(kCard, int(i), scene_.grey_cards[i].R, scene_.grey_cards[i].t, scene_.grey_cards[i].size_m);
  for (size_t b = 0; b < scene_.boards.size(); ++b)
    add_square(kBoard, int(b), scene_.boards[b].R, scene_.boards[b].t, scene_.boards[b].size_m);
  return casters;
}

std::vector<RigRenderer::ShadowCaster> RigRenderer::CastersNear(const std::vector<ShadowCaster>& casters,
                                                               const Eigen::Vector3d& light,
                                                               const Eigen::Vector3d& centre, double radius) {
  const Eigen::Vector3d to_centre = centre - light;
  const double distance = to_centre.norm();
  if (distance <= radius) return casters;  // the light is among the points
  // Every point's direction from the light lies within `spread` of `towards`; a caster's cone
  // can hold one only if its axis lies within spread + its half-angle (a margin for rounding).
  const Eigen::Vector3d towards = to_centre / distance;
  const double spread = std::asin(radius / distance);
  std::vector<ShadowCaster> near;
  for (const ShadowCaster& c : casters) {
    const double half_angle = c.cos_half_angle < 0 ? std::numbers::pi : std::acos(c.cos_half_angle);
    const double apart = std::acos(std::clamp(towards.dot(c.axis), -1.0, 1.0));
    if (apart <= spread + half_angle + 1e-6) near.push_back(c);
  }
  return near;
}

bool RigRenderer::Occluded(const Eigen::Vector3d& p, const Eigen::Vector3d& light,
                           const std::vector<ShadowCaster>& casters, Kind self_kind, int self_index) const {
  if (casters.empty()) return false;  // most of a shot: no caster's cone reaches the tile
  const Eigen::Vector3d to_light = light - p;
  const double dist = to_light.norm();
  for (const ShadowCaster& c : casters) {
    if (c.kind == self_kind && c.index == self_index) continue;
    // The segment from the light towards p must enter the caster's cone: -to_light / dist is
    // that direction (compared without dividing).
    if (-to_light.dot(c.axis) < c.cos_half_angle * dist) continue;
    if (Blocks(c, p, to_light / dist, dist)) return true;
  }
  return false;
}

RigRenderer::Paint RigRenderer::PaintAt(const Sample& s) const {
  const Eigen::Vector3d p(s.x, s.y, s.z);
  if (s.kind == kCard) {
    const auto& c = scene_.grey_cards[s.index];
    const Eigen::Vector3d q = c.R.transpose() * (p - c.t);
    if (std::abs(q.x()) <= c.patch_m / 2 && std::abs(q.y()) <= c.patch_m / 2) return kGreyPatch;
    return TagPaint(c.tags, q.x(), q.y());
  }
  if (s.kind == kBoard) {
    const RigBoard& board = scene_.boards[s.index];
    const Eigen::Vector3d q = board.R.transpose() * (p - board.t);
    if (std::abs(q.x()) <= board.patch_m / 2 && std::abs(q.y()) <= board.patch_m / 2) return kMaterialPatch;
    return TagPaint(board.tags, q.x(), q.y());
  }
  return kWhite;
}

float RigRenderer::PaintAlbedo(const Sample& s) const {
  switch (s.paint) {
    case kGreyPatch: return float(scene_.grey_cards[s.index].albedo);
    case kTagBlack: return float(scene_.tag_black_albedo);
    default: return float(scene_.board_albedo);
  }
}

RigRenderer::Paint RigRenderer::TagPaint(const std::vector<RigTag>& tags, double u, double v) const {
  for (const RigTag& tag : tags) {
    const TagBitmap& bm = tag_bitmaps_[tag.id];
    const double cell = tag.size_m / bm.border_cells;
    const double half = 0.5 * cell * bm.cells;
    const int col = int(std::floor((u - (tag.centre_m.x() - half)) / cell));
    const int row = int(std::floor(((tag.centre_m.y() + half) - v) / cell));
    if (col >= 0 && row >= 0 && col < bm.cells && row < bm.cells)
      return bm.white[size_t(row) * bm.cells + col] ? kWhite : kTagBlack;
  }
  return kWhite;
}

Image RigRenderer::RenderPatchRadiance(int b, const RigShot& shot) const {
  const RigBoard& board = scene_.boards[b];
  const int N = options_.patch_texels;
  const Eigen::Vector3d light_board = board.R.transpose() * (shot.light_m - board.t);
  const Eigen::Vector3d offset(board.material_offset_m.x(), board.material_offset_m.y(), 0);
  Image out(N, N, 3);
  for (int j = 0; j < N; ++j)
    for (int i = 0; i < N; ++i) {
      const PatchTexel& t = patch_texels_[b][size_t(j) * N + i];
      const Eigen::Vector3d p = t.point_board.cast<double>();
      const Eigen::Vector3d to_light = light_board - p;
      const double d2 = to_light.squaredNorm();
      const Eigen::Vector3d wi = to_light / std::sqrt(d2);
      float* px = out.pixel(i, j);
      if (SelfShadowed(material_, p + offset, wi)) continue;  // stays black
      const MaterialHit hit{p + offset, t.normal, t.albedo};
      const Eigen::Vector3f L = ReflectedRadiance(material_, hit, wi, t.wo.cast<double>()) * float(shot.power / d2);
      px[0] = L.x();
      px[1] = L.y();
      px[2] = L.z();
    }
  return out;
}

Eigen::Vector3f RigRenderer::Shade(const Sample& s, const RigShot& shot, const std::vector<Image>& patches,
                                   const std::vector<ShadowCaster>& casters) const {
  if (s.kind == kNone) return Eigen::Vector3f::Zero();
  const Eigen::Vector3d p(s.x, s.y, s.z);
  if (Occluded(p, shot.light_m, casters, s.kind, s.index)) return Eigen::Vector3f::Zero();
  // The material patches (shaded in texture space beforehand) need no light direction here.
  const auto light_direction = [&](float* irradiance) -> Eigen::Vector3d {
    const Eigen::Vector3d to_light = shot.light_m - p;
    const double d2 = to_light.squaredNorm();
    *irradiance = float(shot.power / d2);
    return to_light / std::sqrt(d2);
  };
  auto lambert = [&](const Eigen::Vector3d& n, float albedo) {
    float E = 0;
    const Eigen::Vector3d wi = light_direction(&E);
    return Eigen::Vector3f::Constant(albedo * kInvPi * E * float(std::max(0.0, n.dot(wi))));
  };
  switch (s.kind) {
    case kTable:
      return lambert(scene_.TableNormalInCam(), float(scene_.table_albedo));
    case kCard:
      return lambert(scene_.grey_cards[s.index].R.col(2), PaintAlbedo(s));
    case kBoard: {
      const RigBoard& board = scene_.boards[s.index];
      if (s.paint == kMaterialPatch) {
        const Eigen::Vector3d q = board.R.transpose() * (p - board.t);
        const double half = board.patch_m / 2;
        const Image& tex = patches[s.index];
        const double scale = tex.width() / board.patch_m;
        Eigen::Vector3f L;
        tex.SampleBilinear(float((q.x() + half) * scale), float((half - q.y()) * scale), L.data());
        return L;
      }
      return lambert(board.R.col(2), PaintAlbedo(s));
    }
    case kSphere: {
      float E = 0;
      const Eigen::Vector3d wi = light_direction(&E);
      const RigSphere& sp = scene_.spheres[s.index];
      const Eigen::Vector3d n = (p - sp.center_m).normalized();
      const double cos_i = n.dot(wi);
      if (cos_i <= 0) return Eigen::Vector3f::Zero();
      const Eigen::Vector3d wo = (-p).normalized();
      const double cos_o = std::max(n.dot(wo), 1e-4);
      const Eigen::Vector3d h = (wi + wo).normalized();
      const double a2 = sp.coat_roughness * sp.coat_roughness;
      const double D = GgxDistribution(std::max(n.dot(h), 0.0), a2);
      const double F = SchlickFresnel(sp.coat_f0, wi.dot(h));
      const double spec = F * D * SmithG1(cos_i, a2) * SmithG1(cos_o, a2) / (4 * cos_i * cos_o);
      const Eigen::Vector3f base = (sp.base_rgb * ((1 - F) / std::numbers::pi)).cast<float>();
      return (base + Eigen::Vector3f::Constant(float(spec))) * float(E * cos_i);
    }
    default:
      return Eigen::Vector3f::Zero();
  }
}

Image RigRenderer::RenderShotLinear(int shot_index) const { return RenderFlashLinear(scene_.shots.at(shot_index)); }

Image RigRenderer::RenderFlashLinear(const RigShot& shot) const {
  MESOCAP_CHECK(!gbuffer_.empty(), "Prepare() first");
  std::vector<Image> patches(scene_.boards.size());
  ParallelFor(0, int(patches.size()), [&](int b) { patches[b] = RenderPatchRadiance(b, shot); }, options_.num_threads);
  const int W = scene_.camera.width, H = scene_.camera.height;
  const size_t spp = size_t(options_.samples_per_axis) * options_.samples_per_axis;
  const float scale = float(scene_.exposure / spp);
  const std::vector<ShadowCaster> casters = ShadowCastersFor(shot.light_m);
  // Tiles of pixels share the casters that can shadow any of their points.
  constexpr int kTile = 16;
  Image out = Image::Uninitialized(W, H, 3);
  ParallelFor(0, (H + kTile - 1) / kTile, [&](int tile_row) {
    const int y0 = tile_row * kTile, y1 = std::min(H, y0 + kTile);
    for (int x0 = 0; x0 < W; x0 += kTile) {
      const int x1 = std::min(W, x0 + kTile);
      Eigen::AlignedBox3d box;
      for (int y = y0; y < y1; ++y)
        for (const Sample* s = &gbuffer_[(size_t(y) * W + x0) * spp]; s != &gbuffer_[(size_t(y) * W + x1) * spp]; ++s)
          if (s->kind != kNone) box.extend(Eigen::Vector3d(s->x, s->y, s->z));
      const std::vector<ShadowCaster> near =
          box.isEmpty() ? std::vector<ShadowCaster>{}
                        : CastersNear(casters, shot.light_m, box.center(), 0.5 * box.diagonal().norm() + 1e-9);
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
          Eigen::Vector3f sum = Eigen::Vector3f::Zero();
          const Sample* s = &gbuffer_[(size_t(y) * W + x) * spp];
          for (size_t k = 0; k < spp; ++k) sum += Shade(s[k], shot, patches, near);
          float* px = out.pixel(x, y);
          for (int c = 0; c < 3; ++c) px[c] = sum[c] * scale;
        }
    }
  }, options_.num_threads);
  return out;
}

Image RigRenderer::RenderCalibLinear(int calib_index) const {
  const RigCalibShot& cs = scene_.calib_shots.at(calib_index);
  const RigCheckerboard& cb = scene_.checkerboard;
  const int W = scene_.camera.width, H = scene_.camera.height;
  const auto offsets = SubpixelOffsets();
  const float ambient = float(scene_.ambient_radiance_calib);
  const double sq = cb.square_m;
  // The board's plane in its own frame: the camera at `origin`, a ray (x, y, 1) along R^T (x, y, 1).
  const Eigen::Matrix3d to_board = cs.R.transpose();
  const Eigen::Vector3d origin = -(to_board * cs.t);
  const double lo = -sq - cb.margin_m, hi_x = cb.cols * sq + cb.margin_m, hi_y = cb.rows * sq + cb.margin_m;
  // What a point of the image sees, as a region that is convex on the board's plane: a square of
  // the board (cut by its edge), or one side of the board's outline.
  constexpr int64_t kBehind = -100, kLeft = -1, kRight = -2, kBelow = -3, kAbove = -4;
  const auto region_at = [&](double x, double y) -> int64_t {
    const Eigen::Vector2f u = UndistortedAt(x, y);
    const Eigen::Vector3d d = to_board * Eigen::Vector3d(u.x(), u.y(), 1.0);
    const double s = std::abs(d.z()) < 1e-12 ? -1 : -origin.z() / d.z();
    if (!(s > 0)) return kBehind;
    const double qx = origin.x() + s * d.x(), qy = origin.y() + s * d.y();
    if (qx < lo) return kLeft;
    if (qx > hi_x) return kRight;
    if (qy < lo) return kBelow;
    if (qy > hi_y) return kAbove;
    return (int64_t(std::floor(qx / sq)) + (1 << 20)) << 21 | (int64_t(std::floor(qy / sq)) + (1 << 20));
  };
  const auto albedo_of = [&](int64_t region) {
    if (region < 0) return float(scene_.table_albedo);
    const int a = int((region >> 21) - (1 << 20)), b = int((region & ((1 << 21) - 1)) - (1 << 20));
    const bool in_squares = a >= -1 && a <= cb.cols - 1 && b >= -1 && b <= cb.rows - 1;
    return in_squares && ((a + b) % 2 == 0) ? 0.04f : 0.8f;
  };
  // A pixel whose corners see one region sees it everywhere: within a pixel the undistortion is
  // bilinear and the plane projective, so its samples lie in the corners' convex hull.
  const auto pixel_value = [&](int x, int y, const int64_t* top, const int64_t* bottom) {
    const int64_t r = top[x];
    if (r != kBehind && top[x + 1] == r && bottom[x] == r && bottom[x + 1] == r) return albedo_of(r) * ambient;
    float sum = 0;
    for (const auto& off : offsets) sum += albedo_of(region_at(x - 0.5 + off.x(), y - 0.5 + off.y())) * ambient;
    return sum / offsets.size();
  };
  Image out(W, H, 3);
  // Bands of rows, so that each row of pixel corners is looked up once (the bottom of one pixel
  // row is the top of the next), but for the bands' first rows.
  constexpr int kBandRows = 32;
  ParallelFor(0, (H + kBandRows - 1) / kBandRows, [&](int band) {
    const int y0 = band * kBandRows, y1 = std::min(H, y0 + kBandRows);
    std::vector<int64_t> top(W + 1), bottom(W + 1);
    for (int i = 0; i <= W; ++i) bottom[i] = region_at(i - 0.5, y0 - 0.5);
    for (int y = y0; y < y1; ++y) {
      std::swap(top, bottom);
      for (int i = 0; i <= W; ++i) bottom[i] = region_at(i - 0.5, y + 0.5);
      for (int x = 0; x < W; ++x) {
        float* px = out.pixel(x, y);
        px[0] = px[1] = px[2] = pixel_value(x, y, top.data(), bottom.data());
      }
    }
  }, options_.num_threads);
  return out;
}

void RigRenderer::ApplySensor(Image* image, uint64_t stream) const {
  const uint64_t key = NoiseKey(scene_.options.seed, stream);
  const float* gaussian = GaussianTable().data();
  const float shot = float(scene_.noise_shot), read = float(scene_.noise_read);
  const int values_per_row = image->width() * image->channels();
  ParallelFor(0, image->height(), [&](int y) {
    float* row = image->row(y);
    const uint64_t first = uint64_t(y) * values_per_row, end = first + uint64_t(values_per_row);
    // The row's unit noise first: value `index` takes slot index % 5 of hash index / 5, in runs
    // of one hash each (the first and last runs may be partial).
    thread_local std::vector<float> noise;
    noise.resize(size_t(values_per_row));
    for (uint64_t run = first / kNoiseValuesPerHash; run * kNoiseValuesPerHash < end; ++run) {
      const uint64_t bits = SplitMix64(key ^ run);
      const uint64_t lo = std::max(first, run * kNoiseValuesPerHash);
      const uint64_t hi = std::min(end, (run + 1) * kNoiseValuesPerHash);
      for (uint64_t index = lo; index < hi; ++index)
        noise[index - first] = gaussian[(bits >> (12 * (index - run * kNoiseValuesPerHash))) & 4095];
    }
    // Then the values, in a loop the compiler vectorises (square roots four at a time).
    for (int i = 0; i < values_per_row; ++i) {
      const float v = std::max(row[i], 0.0f);
      row[i] = std::clamp(v + std::sqrt(shot * v + read) * noise[size_t(i)], 0.0f, 1.0f);
    }
  }, options_.num_threads);
}

}  // namespace mesocap

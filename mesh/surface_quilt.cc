#include "mesh/surface_quilt.h"

#include <algorithm>
#include <chrono>
#include <queue>
#include <cmath>
#include <random>

#include "core/progress.h"
#include "core/text_format.h"
#include "mesh/lscm.h"
#include "mesh/triangle_raster.h"
#include "synth/graphcut_fit.h"
#include "synth/patch_matching.h"

namespace mesocap {

int SurfaceQuiltOptions::EffectiveRadius(int sample_width, int sample_height) const {
  return patch_radius > 0 ? patch_radius : std::max(min_patch_radius, std::min(32, (std::min(sample_width, sample_height) - 1) / 2));
}

Status SurfaceQuiltOptions::Check(int sample_width, int sample_height) const {
  if (min_patch_radius < 1) return Status::Error("the minimum patch radius must be at least 1");
  if (!(shrink > 0 && shrink < 1)) return Status::Error("the shrink factor must be in (0, 1)");
  if (!(seam_threshold > 0)) return Status::Error("the seam threshold must be positive");
  if (!(max_area_distortion >= 1)) return Status::Error("the area distortion threshold must be at least 1");
  if (!(texel_size >= 0) || !std::isfinite(texel_size)) return Status::Error("the texel size must be a positive length (or 0)");
  const int r = EffectiveRadius(sample_width, sample_height);
  if (2 * r + 1 > std::min(sample_width, sample_height) || r < min_patch_radius)
    return Status::Error(Format("the sample (%dx%d texels) is smaller than the work patch (%d texels a side)", sample_width,
                                sample_height, 2 * std::max(r, min_patch_radius) + 1));
  return Status::Ok();
}

Eigen::Vector2d ContinueAtlasCoordinate(const SynthMap& map, size_t i, const Eigen::Vector3d& s, const Eigen::Vector3d& t,
                                        const Eigen::Vector3d& offset, double texel_size) {
  const double a = map.rotation_deg[i] * M_PI / 180;
  const Eigen::Vector3d x_axis = std::cos(a) * s + std::sin(a) * t, y_axis = -std::sin(a) * s + std::cos(a) * t;
  return {map.source_x[i] + offset.dot(x_axis) / texel_size, map.source_y[i] - offset.dot(y_axis) / texel_size};
}

namespace {

constexpr double kFoldedAreaShare = 0.01;  // slivers of this share of a work patch's area may fold or stretch

// A work patch laid flat: its faces, their corners in the work image's plane (surface units,
// v at the origin, the field's mean direction along +x, t up), and per face the angle of its
// field direction in that plane.
struct WorkPatch {
  std::vector<int32_t> faces;
  std::vector<std::array<Eigen::Vector2d, 3>> corners;
  std::vector<double> field_angle;  // radians
  bool crosses_charts = false;
};

// The 2D image of a tangent vector under face i's flattening (least squares on its edges).
Eigen::Vector2d FlatDirection(const TriangleMesh& m, int f, const std::array<Eigen::Vector2d, 3>& q, const Eigen::Vector3d& w) {
  const auto& c = m.faces[f];
  Eigen::Matrix<double, 3, 2> E;
  E.col(0) = m.positions[c[1]] - m.positions[c[0]], E.col(1) = m.positions[c[2]] - m.positions[c[0]];
  Eigen::Matrix2d D;
  D.col(0) = q[1] - q[0], D.col(1) = q[2] - q[0];
  const Eigen::Matrix2d gram = E.transpose() * E;
  if (std::abs(gram.determinant()) < 1e-30) return Eigen::Vector2d::Zero();
  return D * gram.inverse() * (E.transpose() * w);
}

class SurfaceQuilter {
 public:
  SurfaceQuilter(const TriangleMesh& mesh, const TangentFrames& frames, const Atlas& atlas, const AtlasTexels& texels,
                 const Image& sample, const SurfaceQuiltOptions& o, SurfaceQuiltReport* report)
      : m_(mesh), frames_(frames), atlas_(atlas), tx_(texels), sample_(sample), o_(o), rep_(*report),
        map_(atlas.size, atlas.size, sample.width(), sample.height(), "quilt"), rng_(o.seed),
        face_neighbours_(FaceNeighbours(mesh)) {
    copies_.push_back(MakeRotatedSample(sample, Image(), 0));
    PatchMatcherOptions mo;
    mo.num_threads = o.num_threads;
    matcher_ = std::make_unique<PatchMatcher>(copies_, mo);
    rep_.sample_neighbour_step = MeanNeighbourStep(sample);
    rep_.patch_radius = o.EffectiveRadius(sample.width(), sample.height());
    rep_.texel_size = h_ = o.texel_size > 0 ? o.texel_size : MeanEdgeLength(mesh);
    rep_.texels = tx_.count();
    filled_.assign(tx_.count(), 0);
    constrained_.assign(tx_.count(), 0);
    // The dense texels of each face, for committing a patch.
    face_texels_.offsets.assign(m_.face_count() + 1, 0);
    for (int d = 0; d < tx_.count(); ++d) ++face_texels_.offsets[tx_.face[d] + 1];
    for (int f = 0; f < m_.face_count(); ++f) face_texels_.offsets[f + 1] += face_texels_.offsets[f];
    face_texels_.list.resize(tx_.count());
    std::vector<int32_t> next(face_texels_.offsets.begin(), face_texels_.offsets.end() - 1);
    for (int d = 0; d < tx_.count(); ++d) face_texels_.list[next[tx_.face[d]]++] = d;
    face_mark_.assign(m_.face_count(), 0);
    vertex_mark_.assign(m_.vertex_count(), 0);
  }

  bool Run(const ProgressFn& progress) {
    int done = 0;
    while (true) {
      const int v = MostConstrained();
      if (v < 0) return true;
      done += PlaceAround(v);
      if (!ReportProgress(progress, done, tx_.count(), "quilting")) return false;
    }
  }

  SynthMap& map() { return map_; }

 private:
  // The unfilled texel with the most filled neighbours (the first in atlas order among equals);
  // a random one when none has any (the first patch, or a part of the mesh not reached yet).
  int MostConstrained() {
    int best = -1, best_count = -1;
    for (int d = 0; d < tx_.count(); ++d)
      if (!filled_[d] && constrained_[d] > best_count) best = d, best_count = constrained_[d];
    if (best >= 0 && best_count == 0) {
      std::vector<int32_t> empty;
      for (int d = 0; d < tx_.count(); ++d)
        if (!filled_[d]) empty.push_back(d);
      best = empty[std::uniform_int_distribution<size_t>(0, empty.size() - 1)(rng_)];
    }
    return best;
  }

  // The faces around v within `reach` of its position (a face's centre less its extent), grown
  // nearest first from v's face and only while they stay a topological disk, so LSCM can lay
  // them flat: a face joins by one edge with its third corner new, or by two edges (filling a
  // notch); a face that would pinch the border or close the surface waits, and joins when a later
  // face makes it a notch.
  std::vector<int32_t> FacesAround(int v, double reach) {
    const Eigen::Vector3d& p = tx_.position[v];
    ++stamp_;
    auto distance = [&](int32_t g) {
      const auto& c = m_.faces[g];
      const Eigen::Vector3d centre = (m_.positions[c[0]] + m_.positions[c[1]] + m_.positions[c[2]]) / 3;
      double extent = 0;
      for (int32_t k : c) extent = std::max(extent, (m_.positions[k] - centre).norm());
      return (centre - p).norm() - extent;
    };
    std::vector<int32_t> faces;
    using Entry = std::pair<double, int32_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
    auto join = [&](int32_t g) {
      faces.push_back(g);
      face_mark_[g] = stamp_;
      for (int32_t k : m_.faces[g]) vertex_mark_[k] = stamp_;
      for (int32_t n : face_neighbours_[g])
        if (n >= 0 && face_mark_[n] != stamp_) {
          const double d = distance(n);
          if (d <= reach) queue.push({d, n});
        }
    };
    join(tx_.face[v]);
    while (!queue.empty()) {
      const int32_t g = queue.top().second;
      queue.pop();
      if (face_mark_[g] == stamp_) continue;
      int shared = 0, corners_in = 0;
      for (int32_t n : face_neighbours_[g]) shared += n >= 0 && face_mark_[n] == stamp_;
      for (int32_t k : m_.faces[g]) corners_in += vertex_mark_[k] == stamp_;
      if (shared == 2 || (shared == 1 && corners_in == 2)) join(g);
    }
    return faces;
  }

  // Scales a work patch's flat corners to surface units (the patch's area kept), counter-clockwise,
  // v at the origin; false when they fold or stretch a face's area by more than T_d (slivers of at
  // most kFoldedAreaShare of the area left out of the measure: a marched surface's slivers flatten
  // wildly).
  bool ToSurfaceUnits(int v, WorkPatch* wp) const {
    double area3 = 0, area2 = 0;
    std::vector<double> a3(wp->faces.size()), a2(wp->faces.size());
    for (size_t i = 0; i < wp->faces.size(); ++i) {
      const auto& q = wp->corners[i];
      a3[i] = m_.FaceArea(wp->faces[i]);
      a2[i] = 0.5 * ((q[1] - q[0]).x() * (q[2] - q[0]).y() - (q[1] - q[0]).y() * (q[2] - q[0]).x());
      area3 += a3[i], area2 += a2[i];
    }
    if (area2 < 0) {  // laid flat clockwise (an atlas' rows run down): mirror
      for (auto& q : wp->corners)
        for (auto& p : q) p.y() = -p.y();
      for (double& a : a2) a = -a;
      area2 = -area2;
    }
    if (!(area2 > 0) || !(area3 > 0)) return false;
    const double scale = std::sqrt(area3 / area2);
    std::vector<std::pair<double, double>> stretch(wp->faces.size());  // distortion, surface area
    for (size_t i = 0; i < wp->faces.size(); ++i) {
      const double s = a2[i] * scale * scale / std::max(a3[i], 1e-300);
      stretch[i] = {s > 0 ? std::max(s, 1 / s) : HUGE_VAL, a3[i]};
    }
    std::sort(stretch.begin(), stretch.end(), std::greater<>());
    double left_out = 0;
    for (const auto& [distortion, area] : stretch) {
      if ((left_out += area) <= kFoldedAreaShare * area3) continue;
      if (distortion > o_.max_area_distortion) return false;
      break;
    }
    const size_t vi = size_t(std::find(wp->faces.begin(), wp->faces.end(), tx_.face[v]) - wp->faces.begin());
    const Eigen::Vector3d vw = tx_.weights[v].cast<double>();
    const Eigen::Vector2d origin = vw[0] * wp->corners[vi][0] + vw[1] * wp->corners[vi][1] + vw[2] * wp->corners[vi][2];
    for (auto& q : wp->corners)
      for (auto& p : q) p = scale * (p - origin);
    return true;
  }

  // The work patch for a window of radius r around v, or false when its faces are not a disk or
  // the flattening stretches a face's area beyond T_d. Inside one chart the atlas already lays the
  // faces flat (Zhou takes the chart's own sub-image there); across charts, or where the chart
  // stretches more than T_d, LSCM lays them flat.
  bool MakeWorkPatch(int v, int r, WorkPatch* wp) {
    const auto start = std::chrono::steady_clock::now();
    const double reach = (r + 1) * h_ + tx_.spacing;  // a disk of radius r_w, as Zhou pictures the work patch
    wp->faces = r > 0 ? FacesAround(v, reach) : std::vector<int32_t>{tx_.face[v]};
    const int32_t chart = atlas_.face_chart[tx_.face[v]];
    wp->crosses_charts = std::any_of(wp->faces.begin(), wp->faces.end(), [&](int32_t f) { return atlas_.face_chart[f] != chart; });
    bool flat = false;
    if (!wp->crosses_charts) {
      wp->corners.resize(wp->faces.size());
      for (size_t i = 0; i < wp->faces.size(); ++i) wp->corners[i] = atlas_.corner_uv[wp->faces[i]];
      flat = ToSurfaceUnits(v, wp);
    }
    if (!flat) {
      wp->corners = FlattenByLscm(m_, wp->faces, kFoldedAreaShare);
      flat = !wp->corners.empty() && ToSurfaceUnits(v, wp);
    }
    rep_.seconds_flattening += SecondsSince(start);
    if (!flat) return false;
    // The field's mean direction, weighted by area and nearness to v; t must come out to its left.
    Eigen::Vector2d mean_s = Eigen::Vector2d::Zero(), mean_t = Eigen::Vector2d::Zero();
    std::vector<Eigen::Vector2d> s2(wp->faces.size());
    for (size_t i = 0; i < wp->faces.size(); ++i) {
      const int f = wp->faces[i];
      const LocalFrame fr = FaceFrame(m_, frames_, f, Eigen::Vector3d::Constant(1.0 / 3));
      s2[i] = FlatDirection(m_, f, wp->corners[i], fr.s);
      const Eigen::Vector2d t2 = FlatDirection(m_, f, wp->corners[i], fr.t);
      const Eigen::Vector2d centre = (wp->corners[i][0] + wp->corners[i][1] + wp->corners[i][2]) / 3;
      const double weight = m_.FaceArea(f) * std::exp(-centre.squaredNorm() / (reach * reach));
      if (s2[i].norm() > 0) mean_s += weight * s2[i].normalized();
      if (t2.norm() > 0) mean_t += weight * t2.normalized();
    }
    if (mean_s.x() * mean_t.y() - mean_s.y() * mean_t.x() < 0) {  // the flattening mirrors the frame: flip y
      for (auto& q : wp->corners)
        for (auto& p : q) p.y() = -p.y();
      for (auto& d : s2) d.y() = -d.y();
      mean_s.y() = -mean_s.y();
    }
    const double turn = mean_s.norm() > 0 ? std::atan2(mean_s.y(), mean_s.x()) : 0;
    const Eigen::Matrix2d R = Eigen::Rotation2Dd(-turn).toRotationMatrix();
    for (auto& q : wp->corners)
      for (auto& p : q) p = R * p;
    wp->field_angle.resize(wp->faces.size());
    for (size_t i = 0; i < wp->faces.size(); ++i) {
      const Eigen::Vector2d d = R * s2[i];
      wp->field_angle[i] = d.norm() > 0 ? std::atan2(d.y(), d.x()) : 0;
    }
    return true;
  }

  // The work image (cells at one sample texel, row j running down against t) for radius r: per
  // cell the dense texel under it (or -1) and which work patch face it lies in.
  struct WorkImage {
    int radius = 0, side = 0;
    std::vector<int32_t> texel, patch_face;
    std::vector<Eigen::Vector3d> point;  // the surface point under each covered cell
  };

  Eigen::Vector2d CellOf(const Eigen::Vector2d& p, int r) const { return {p.x() / h_ + r, -p.y() / h_ + r}; }

  WorkImage Rasterise(const WorkPatch& wp, int r) const {
    WorkImage wi;
    wi.radius = r, wi.side = 2 * r + 1;
    wi.texel.assign(size_t(wi.side) * wi.side, -1);
    wi.patch_face.assign(wi.texel.size(), -1);
    wi.point.assign(wi.texel.size(), Eigen::Vector3d::Zero());
    for (size_t i = 0; i < wp.faces.size(); ++i) {
      std::array<Eigen::Vector2d, 3> cells;
      for (int k = 0; k < 3; ++k) cells[k] = CellOf(wp.corners[i][k], r);
      const int f = wp.faces[i];
      ForEachGridPointIn(cells, wi.side, 0, wi.side, 0.0, -1e-9, [&](int x, int y, const Eigen::Vector3d& w) {
        const size_t k = size_t(y) * wi.side + x;
        if (wi.patch_face[k] >= 0) return;
        wi.patch_face[k] = int32_t(i);
        const auto& corner = m_.faces[f];
        wi.point[k] = w[0] * m_.positions[corner[0]] + w[1] * m_.positions[corner[1]] + w[2] * m_.positions[corner[2]];
        const auto& uv = atlas_.corner_uv[f];
        wi.texel[k] = NearestTexel(w[0] * uv[0] + w[1] * uv[1] + w[2] * uv[2], atlas_.face_chart[f]);
      });
    }
    return wi;
  }

  // The dense texel at atlas point a, or the nearest one of the same chart beside it.
  int NearestTexel(const Eigen::Vector2d& a, int32_t chart) const {
    const int ax = int(std::floor(a.x())), ay = int(std::floor(a.y()));
    int best = tx_.At(ax, ay);
    if (best >= 0 && atlas_.face_chart[tx_.face[best]] == chart) return best;
    best = -1;
    double best_d = 1e300;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int d = tx_.At(ax + dx, ay + dy);
        if (d < 0 || atlas_.face_chart[tx_.face[d]] != chart) continue;
        const double dist = (Eigen::Vector2d(ax + dx + 0.5, ay + dy + 0.5) - a).squaredNorm();
        if (dist < best_d) best = d, best_d = dist;
      }
    return best;
  }

  // The work canvas: filled cells hold their texel's value and its patch's orientation in the image.
  SynthCanvas Canvas(const WorkPatch& wp, const WorkImage& wi) const {
    SynthCanvas canvas(wi.side, wi.side, sample_, "quilt");
    for (int y = 0; y < wi.side; ++y)
      for (int x = 0; x < wi.side; ++x) {
        const size_t k = size_t(y) * wi.side + x;
        const int d = wi.texel[k];
        if (d < 0 || !filled_[d]) continue;
        // The texel's patch continued from the texel's centre to the cell's point.
        const size_t a = map_.index(tx_.x[d], tx_.y[d]);
        const LocalFrame fr = FaceFrame(m_, frames_, tx_.face[d], tx_.weights[d].cast<double>());
        const Eigen::Vector2d c = ContinueAtlasCoordinate(map_, a, fr.s, fr.t, wi.point[k] - tx_.position[d], h_);
        const float sx = float(std::clamp(c.x(), 0.0, sample_.width() - 1e-3)), sy = float(std::clamp(c.y(), 0.0, sample_.height() - 1e-3));
        const double angle = map_.rotation_deg[a] + wp.field_angle[wi.patch_face[k]] * 180 / M_PI;
        canvas.map.Set(x, y, sx, sy, float(angle), map_.patch[a]);
        canvas.synthesized[k] = 1;
        std::copy_n(sample_.pixel(int(sx), int(sy)), sample_.channels(), canvas.features.pixel(x, y));
      }
    return canvas;
  }

  MatchResult Match(const SynthCanvas& canvas, int side) {
    const RotatedSample& c = copies_[0];
    if (std::none_of(canvas.synthesized.begin(), canvas.synthesized.end(), [](uint8_t s) { return s; })) {
      MatchResult m;
      m.found = true;
      m.u = std::uniform_int_distribution<int>(0, c.size_x - side)(rng_);
      m.v = std::uniform_int_distribution<int>(0, c.size_y - side)(rng_);
      return m;
    }
    MatchWindow w;
    w.width = w.height = side;
    w.features = &canvas.features;
    w.synthesized = &canvas.synthesized;
    const auto start = std::chrono::steady_clock::now();
    MatchResult m = matcher_->BestMatch(w);
    rep_.seconds_matching += SecondsSince(start);
    return m;
  }

  // One patch around v; returns the texels it filled.
  int PlaceAround(int v) {
    WorkPatch wp;
    int r = rep_.patch_radius;
    while (!MakeWorkPatch(v, r, &wp)) {
      ++rep_.rejected_flattenings;
      if (r > o_.min_patch_radius) {
        r = std::max(o_.min_patch_radius, int(r * o_.shrink));
        continue;
      }
      if (MakeWorkPatch(v, 0, &wp)) break;  // v's own face, laid flat exactly
      return FillAlone(v);                  // a face too thin to lay flat in floating point
    }
    while (true) {
      const WorkImage wi = Rasterise(wp, r);
      SynthCanvas canvas = Canvas(wp, wi);
      const MatchResult match = Match(canvas, wi.side);
      MESOCAP_CHECK(match.found, "the work window is larger than the sample");
      PlacedPatch patch;
      patch.copy = &copies_[0];
      patch.u0 = match.u, patch.v0 = match.v;
      patch.x0 = patch.y0 = 0, patch.width = patch.height = wi.side;
      std::vector<FitFreedom> freedom = DefaultFreedom(canvas, patch);
      for (int y = 0; y < wi.side; ++y)  // the window's rim keeps what the surface around it has
        for (int x = 0; x < wi.side; ++x)
          if ((x == 0 || y == 0 || x == wi.side - 1 || y == wi.side - 1) && canvas.synthesized[size_t(y) * wi.side + x])
            freedom[size_t(y) * wi.side + x] = FitFreedom::kForceOld;
      const auto start = std::chrono::steady_clock::now();
      const CutResult cut = FitPatch(canvas, patch, freedom);
      rep_.seconds_cutting += SecondsSince(start);
      if (cut.mean_seam_cost() > o_.seam_threshold * rep_.sample_neighbour_step && r > o_.min_patch_radius) {
        ++rep_.rejected_cuts;
        r = std::max(o_.min_patch_radius, int(r * o_.shrink));
        continue;
      }
      seam_cost_ += cut.seam_cost, seam_edges_ += cut.seam_edges;
      rep_.mean_seam_cost = seam_edges_ ? seam_cost_ / seam_edges_ : 0;
      ++rep_.patches;
      rep_.chart_crossing_patches += wp.crosses_charts;
      return Commit(v, wp, wi, patch, cut);
    }
  }

  // v alone, from a random texel of the sample (a face with no area in floating point).
  int FillAlone(int v) {
    const float sx = float(std::uniform_int_distribution<int>(0, sample_.width() - 1)(rng_)) + 0.5f;
    const float sy = float(std::uniform_int_distribution<int>(0, sample_.height() - 1)(rng_)) + 0.5f;
    map_.Set(tx_.x[v], tx_.y[v], sx, sy, 0.f, next_patch_++);
    filled_[v] = 1;
    for (const int32_t* e = tx_.neighbours.begin(v); e != tx_.neighbours.end(v); ++e) ++constrained_[*e];
    return 1;
  }

  // Every dense texel of the patch's faces whose cell took the new patch copies the sample under
  // its own position in the work image.
  int Commit(int v, const WorkPatch& wp, const WorkImage& wi, const PlacedPatch& patch, const CutResult& cut) {
    const int32_t id = next_patch_++;
    const Eigen::Vector2d origin = patch.copy->origin;
    int filled = 0;
    for (size_t i = 0; i < wp.faces.size(); ++i) {
      const int f = wp.faces[i];
      for (const int32_t* d = face_texels_.begin(f); d != face_texels_.end(f); ++d) {
        const Eigen::Vector3d w = tx_.weights[*d].cast<double>();
        const Eigen::Vector2d p = w[0] * wp.corners[i][0] + w[1] * wp.corners[i][1] + w[2] * wp.corners[i][2];
        const Eigen::Vector2d c = CellOf(p, wi.radius);
        const int cx = int(std::lround(c.x())), cy = int(std::lround(c.y()));
        // v always takes the patch (its centre may lie just off its face, under a cell another
        // face's texel keeps): each patch fills at least v.
        const bool inside = cx >= 0 && cy >= 0 && cx < wi.side && cy < wi.side;
        if (*d != v && (!inside || !cut.take_new[size_t(cy) * wi.side + cx])) continue;
        const double sx = std::clamp(origin.x() + patch.u0 + c.x(), 0.0, sample_.width() - 1e-3);
        const double sy = std::clamp(origin.y() + patch.v0 + c.y(), 0.0, sample_.height() - 1e-3);
        map_.Set(tx_.x[*d], tx_.y[*d], float(sx), float(sy), float(-wp.field_angle[i] * 180 / M_PI), id);
        if (filled_[*d]) continue;
        filled_[*d] = 1, ++filled;
        for (const int32_t* e = tx_.neighbours.begin(*d); e != tx_.neighbours.end(*d); ++e) ++constrained_[*e];
      }
    }
    return filled;
  }

  const TriangleMesh& m_;
  const TangentFrames& frames_;
  const Atlas& atlas_;
  const AtlasTexels& tx_;
  const Image& sample_;
  SurfaceQuiltOptions o_;
  SurfaceQuiltReport& rep_;
  SynthMap map_;
  std::mt19937 rng_;
  std::vector<std::array<int32_t, 3>> face_neighbours_;
  std::vector<RotatedSample> copies_;
  std::unique_ptr<PatchMatcher> matcher_;
  VertexAdjacency face_texels_;
  std::vector<uint8_t> filled_;
  std::vector<int32_t> constrained_;
  std::vector<int32_t> face_mark_, vertex_mark_;
  int32_t stamp_ = 0, next_patch_ = 0;
  double h_ = 0, seam_cost_ = 0;
  long seam_edges_ = 0;
};

}  // namespace

StatusOr<SynthMap> SurfaceQuiltSynthesis(const TriangleMesh& mesh, const TangentFrames& frames, const Atlas& atlas,
                                         const AtlasTexels& texels, const Image& sample, const SurfaceQuiltOptions& options,
                                         SurfaceQuiltReport* report, const ProgressFn& progress) {
  MESOCAP_RETURN_IF_ERROR(options.Check(sample.width(), sample.height()));
  if (frames.size() != mesh.vertex_count()) return Status::Error("the frames do not belong to the mesh");
  if (int(atlas.corner_uv.size()) != mesh.face_count()) return Status::Error("the atlas does not belong to the mesh");
  const auto start = std::chrono::steady_clock::now();
  SurfaceQuiltReport local;
  SurfaceQuiltReport& rep = report ? *report : local;
  rep = {};
  SurfaceQuilter quilter(mesh, frames, atlas, texels, sample, options, &rep);
  if (!quilter.Run(progress)) return Status::Cancelled();
  rep.seconds = SecondsSince(start);
  return std::move(quilter.map());
}

}  // namespace mesocap

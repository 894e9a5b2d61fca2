// Renders the virtual rig's photographs. The camera and target never move, so what each
// sub-pixel sample sees (object and point) is traced once into a geometry buffer; each flash
// shot then only shades: material patches in texture space (btf_render), everything else per
// sample, with shadows from the balls and boards.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "capture/btf_render.h"
#include "capture/rig_material.h"
#include "capture/rig_scene.h"
#include "capture/tag_pattern.h"
#include "core/image.h"
#include "core/progress.h"

namespace mesocap {

struct RigRenderOptions {
  int samples_per_axis = 2;  // anti-aliasing: samples_per_axis^2 stratified samples a pixel
  int patch_texels = 512;    // texture-space resolution of each material patch per shot
  int num_threads = -1;      // -1: all cores
  std::string Check() const;
};

// Samples per texel axis a true slice of `size` texels needs to be what a shot of this rig can
// see: the texel's average over the points the rig shades its patch with (patch_texels a side),
// at least 2 x 2. Finer truth holds detail no shot can; coarser leaves its histograms wider than
// any texel average's (pixel W1 0.0009-0.0057 from the converged one at 64 texels).
int RigTruthSamplesPerAxis(int size, const RigRenderOptions& rig = {});

class RigRenderer {
 public:
  RigRenderer(const RigScene& scene, const Material& material, const RigRenderOptions& options = {});

  // Traces the geometry buffer and the patches' view rays (once per session).
  void Prepare(const ProgressFn& progress = nullptr);

  // Linear pixel values (radiance x exposure), no noise, no clipping.
  Image RenderShotLinear(int shot_index) const;
  // A flash shot with the flash anywhere (the virtual camera's requested positions).
  Image RenderFlashLinear(const RigShot& shot) const;
  Image RenderCalibLinear(int calib_index) const;
  // Adds shot and read noise and clips to [0, 1]; deterministic in (seed, stream).
  void ApplySensor(Image* image, uint64_t stream) const;

  const RigScene& scene() const { return scene_; }

  enum Kind : uint8_t { kNone = 0, kTable, kBoard, kSphere, kCard };
  // True when a ball or a board (other than `self`) blocks the segment from `p` to `light`.
  bool Occluded(const Eigen::Vector3d& p, const Eigen::Vector3d& light, Kind self_kind, int self_index) const;

  // A board or card in its own frame (x, y across it, z along its normal), made once so that a
  // ray or segment test costs one rotation: a point p is there Local(p).
  struct SquareFrame {
    Eigen::Matrix3d to_local = Eigen::Matrix3d::Identity();
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();  // to_local * the square's centre
    double half = 0;                                   // half its side
    static SquareFrame Of(const Eigen::Matrix3d& R, const Eigen::Vector3d& centre, double size);
    Eigen::Vector3d Local(const Eigen::Vector3d& p) const { return to_local * p - origin; }
    bool Covers(double x, double y) const { return std::abs(x) <= half && std::abs(y) <= half; }
  };

  // An object that may cast a shadow from one light, with the cone (apex at the light) that holds
  // its bounding sphere: a point outside every cone is lit without testing any object.
  struct ShadowCaster {
    Kind kind;
    int index;
    Eigen::Vector3d axis;  // unit, light -> bounding-sphere centre
    double cos_half_angle;  // -1 when the light is inside the bounding sphere
    SquareFrame square;     // boards and cards: their frame, and the light in it
    Eigen::Vector3d light_local = Eigen::Vector3d::Zero();
  };
  std::vector<ShadowCaster> ShadowCastersFor(const Eigen::Vector3d& light) const;
  // Of `casters`, those whose cone can hold a point within `radius` of `centre`: the same answers
  // for every such point, fewer cones to test (a tile of pixels shares one list).
  static std::vector<ShadowCaster> CastersNear(const std::vector<ShadowCaster>& casters, const Eigen::Vector3d& light,
                                               const Eigen::Vector3d& centre, double radius);
  // Occluded(), testing only the casters whose cone holds `p`: the same answer, faster.
  bool Occluded(const Eigen::Vector3d& p, const Eigen::Vector3d& light, const std::vector<ShadowCaster>& casters,
                Kind self_kind, int self_index) const;

 private:
  // What a board's or card's point is painted with; it does not change between shots.
  enum Paint : uint8_t { kMaterialPatch = 0, kGreyPatch, kWhite, kTagBlack };
  struct Sample {
    float x, y, z;  // hit point, camera frame
    Kind kind;
    uint8_t index;
    Paint paint;    // boards and cards
  };
  struct PatchTexel {
    Eigen::Vector3f point_board;  // surface point seen, board frame (material offset removed)
    Eigen::Vector3f normal;
    Eigen::Vector3f albedo;
    Eigen::Vector3f wo;           // toward the camera, board frame
  };

  Sample TracePrimary(const Eigen::Vector3d& ray) const;
  Paint TagPaint(const std::vector<RigTag>& tags, double u, double v) const;  // white mount with tags
  Paint PaintAt(const Sample& s) const;
  float PaintAlbedo(const Sample& s) const;
  Image RenderPatchRadiance(int board, const RigShot& shot) const;
  Eigen::Vector3f Shade(const Sample& s, const RigShot& shot, const std::vector<Image>& patches,
                        const std::vector<ShadowCaster>& casters) const;
  // Whether the caster lies between p and the light (unit direction d, at distance dist).
  bool Blocks(const ShadowCaster& caster, const Eigen::Vector3d& p, const Eigen::Vector3d& d, double dist) const;
  std::vector<Eigen::Vector2d> SubpixelOffsets() const;
  // Camera ray through continuous pixel position (x, y), interpolated in ray_grid_.
  Eigen::Vector3d RayThrough(double x, double y) const;
  // The same ray as undistorted normalised coordinates (x, y) of the direction (x, y, 1).
  Eigen::Vector2f UndistortedAt(double x, double y) const;

  // A board or card as primary rays from the camera (at the origin) meet it: its frame (the
  // camera is at -square.origin there), and the cone from the camera that holds it (rays outside
  // miss it).
  struct PrimarySquare {
    SquareFrame square;
    Eigen::Vector3d axis;   // unit, camera -> the square's centre
    double cos_half_angle;  // -1 when the camera is inside its bounding sphere
  };
  double IntersectPrimary(const PrimarySquare& square, const Eigen::Vector3d& ray) const;

  RigScene scene_;
  const Material& material_;
  std::vector<PrimarySquare> primary_squares_;  // boards, then cards
  RigRenderOptions options_;
  std::vector<TagBitmap> tag_bitmaps_;  // by tag id
  // Undistorted normalised coordinates at pixel corners ((W+1) x (H+1), node (i, j) at pixel
  // position (i - 0.5, j - 0.5)): undistortion once, bilinear after (error < 1e-3 px).
  std::vector<Eigen::Vector2f> ray_grid_;
  std::vector<Sample> gbuffer_;         // width * height * spp
  std::vector<std::vector<PatchTexel>> patch_texels_;  // per board
};

}  // namespace mesocap

#include "capture/btf_render.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/directions.h"
#include "core/ggx.h"
#include "core/parallel.h"
#include "core/pbr_brdf.h"

namespace mesocap {

MaterialHit TraceFromViewer(const Material& m, double x, double y, const Eigen::Vector3d& wo) {
  const double horizontal = std::hypot(wo.x(), wo.y());
  double s_hit = 0;
  if (horizontal > 1e-9 && m.max_height_m() > 0) {
    // March from where the ray enters the slab z <= max height down to the reference plane,
    // half a cell of horizontal travel per step, then bisect the crossing.
    const double s_top = m.max_height_m() / wo.z();
    const double ds = 0.5 * m.cell_m() / horizontal;
    auto above = [&](double s) {
      return s * wo.z() > m.Height(x + s * wo.x(), y + s * wo.y());
    };
    double s_prev = s_top, s = s_top;
    while (s > 0) {
      s = std::max(0.0, s - ds);
      if (!above(s)) break;
      s_prev = s;
    }
    double lo = s, hi = s_prev;  // lo below the surface (or 0), hi above
    for (int it = 0; it < 8 && hi - lo > 1e-12; ++it) {
      const double mid = 0.5 * (lo + hi);
      (above(mid) ? hi : lo) = mid;
    }
    s_hit = hi;
  }
  const double hx = x + s_hit * wo.x(), hy = y + s_hit * wo.y();
  MaterialHit hit;
  hit.point = {hx, hy, double(m.Height(hx, hy))};
  hit.normal = m.Normal(hx, hy);
  hit.albedo = m.Albedo(hx, hy);
  return hit;
}

bool SelfShadowed(const Material& m, const Eigen::Vector3d& p, const Eigen::Vector3d& wi) {
  if (wi.z() <= 0) return true;
  const double horizontal = std::sqrt(wi.x() * wi.x() + wi.y() * wi.y());
  if (horizontal < 1e-9 || m.max_height_m() <= 0) return false;
  const double ds = m.cell_m() / horizontal;
  const double s_end = (m.max_height_m() - p.z()) / wi.z();
  for (double s = ds; s < s_end; s += ds) {
    const Eigen::Vector3d q = p + s * wi;
    if (q.z() < m.Height(q.x(), q.y()) - 1e-6) return true;
  }
  return false;
}

Eigen::Vector3f ReflectedRadiance(const Material& m, const MaterialHit& hit, const Eigen::Vector3d& wi,
                                  const Eigen::Vector3d& wo) {
  const Eigen::Vector3d n = hit.normal.cast<double>();
  if (m.uses_pbr_brdf())
    return PbrReflectance({hit.albedo.cast<double>(), m.pbr_roughness(), m.pbr_metallic()}, n, wi, wo).cast<float>();
  const double cos_i = n.dot(wi);
  if (cos_i <= 0) return Eigen::Vector3f::Zero();
  Eigen::Vector3f f = hit.albedo / float(std::numbers::pi);
  if (m.specular_f0() > 0) {
    const double cos_o = std::max(n.dot(wo), 1e-3);
    const double a2 = m.roughness() * m.roughness();
    const Eigen::Vector3d h = (wi + wo).normalized();
    const double D = GgxDistribution(std::max(n.dot(h), 0.0), a2);
    const double G = SmithG1(cos_i, a2) * SmithG1(cos_o, a2);
    const double F = SchlickFresnel(m.specular_f0(), wi.dot(h));
    f += Eigen::Vector3f::Constant(float(F * D * G / (4 * cos_i * cos_o)));
  }
  return f * float(cos_i);
}

TrueBtfRequest TrueBtfRequestFor(const Eigen::Vector3d& light, const Eigen::Vector3d& view, int size, int samples_per_axis) {
  const Eigen::Vector2d i = AnglesDegFromDirection(light), o = AnglesDegFromDirection(view);
  TrueBtfRequest r;
  r.theta_i_deg = i.x(), r.phi_i_deg = i.y(), r.theta_o_deg = o.x(), r.phi_o_deg = o.y();
  r.size = size;
  r.samples_per_axis = samples_per_axis;
  return r;
}

TrueBtfFrame::TrueBtfFrame(const TrueBtfRequest& r) {
  // A turned material is the plain one seen through the inverse turn: points and directions by -r.
  const Eigen::Matrix3d material_from_patch =
      Eigen::AngleAxisd(-DegToRad(r.material_rotation_deg), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  wi = material_from_patch * DirectionFromAnglesDeg(r.theta_i_deg, r.phi_i_deg);
  wo = material_from_patch * DirectionFromAnglesDeg(r.theta_o_deg, r.phi_o_deg);
  turn = material_from_patch.topLeftCorner<2, 2>();
}

Eigen::Vector2d TexelSamplePoint(const TrueBtfRequest& r, const TrueBtfFrame& frame, int i, int j, int sx, int sy) {
  const int n = std::max(1, r.samples_per_axis);
  const double texel_m = r.patch_m / r.size;
  const Eigen::Vector2d centre = TexelCentre(i, j, r.size, r.patch_m);
  return frame.turn * (centre + texel_m * Eigen::Vector2d((sx + 0.5) / n - 0.5, (sy + 0.5) / n - 0.5)) + r.offset_m;
}

Eigen::Vector3f LitRadiance(const Material& m, const MaterialHit& hit, const Eigen::Vector3d& wi, const Eigen::Vector3d& wo) {
  return SelfShadowed(m, hit.point, wi) ? Eigen::Vector3f::Zero() : ReflectedRadiance(m, hit, wi, wo);
}

Image RenderTrueBtfSlice(const Material& m, const TrueBtfRequest& r, int num_threads) {
  const TrueBtfFrame frame(r);
  Image out(r.size, r.size, 3);
  ParallelFor(0, r.size, [&](int j) {
    const int n = std::max(1, r.samples_per_axis);
    for (int i = 0; i < r.size; ++i) {
      Eigen::Vector3f L = Eigen::Vector3f::Zero();
      for (int sy = 0; sy < n; ++sy)
        for (int sx = 0; sx < n; ++sx) {
          const Eigen::Vector2d xy = TexelSamplePoint(r, frame, i, j, sx, sy);
          L += LitRadiance(m, TraceFromViewer(m, xy.x(), xy.y(), frame.wo), frame.wi, frame.wo);
        }
      L /= float(n * n);
      float* px = out.pixel(i, j);
      px[0] = L.x();
      px[1] = L.y();
      px[2] = L.z();
    }
  }, num_threads);
  return out;
}

}  // namespace mesocap

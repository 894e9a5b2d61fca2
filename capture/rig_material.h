// Procedural materials of the virtual rig: a height field with mesostructure over a periodic
// tile, a spatially varying albedo, and one GGX specular lobe over a Lambertian base.
// Coordinates are metres in the material's own plane; everything is periodic in tile_m, so
// rays that march past a patch's edge keep finding material.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "capture/material_catalog.h"
#include "core/status.h"

namespace mesocap {

class Material {
 public:
  // Builds a catalog material; the texture is fixed per name (not per session seed), so the
  // true BTF of a name is always the same.
  static StatusOr<Material> Create(const std::string& name);

  const std::string& name() const { return name_; }
  double tile_m() const { return tile_m_; }
  double max_height_m() const { return max_height_m_; }
  double cell_m() const { return tile_m_ / grid_; }
  double specular_f0() const { return specular_f0_; }
  double roughness() const { return roughness_; }  // GGX alpha
  // Materials rendered with the glTF metallic-roughness BRDF (core/pbr_brdf.h) instead of the
  // Lambertian + GGX lobe: the base colour is the albedo grid.
  bool uses_pbr_brdf() const { return pbr_; }
  double pbr_roughness() const { return pbr_roughness_; }  // perceptual (alpha = its square)
  double pbr_metallic() const { return pbr_metallic_; }

  // Bilinear lookups, periodic.
  float Height(double x_m, double y_m) const;
  Eigen::Vector3f Albedo(double x_m, double y_m) const;
  Eigen::Vector3f Normal(double x_m, double y_m) const;  // unit, z up

 private:
  void FinishGrids();  // normals and max height from the height grid
  template <typename T, typename Fn>
  T Lerp(const std::vector<T>& grid, double x_m, double y_m, Fn&& get) const;

  std::string name_;
  double tile_m_ = 0.096;
  int grid_ = 1280;
  double max_height_m_ = 0;
  double specular_f0_ = 0.04, roughness_ = 0.3;
  bool pbr_ = false;
  double pbr_roughness_ = 0, pbr_metallic_ = 0;
  std::vector<float> height_;           // grid_ * grid_
  std::vector<Eigen::Vector3f> albedo_;  // grid_ * grid_
  std::vector<Eigen::Vector3f> normal_;  // grid_ * grid_
};

}  // namespace mesocap

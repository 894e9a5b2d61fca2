#include "app/dressed_gltf.h"

#include <map>

#include "app/material_maps.h"
#include "export/gltf_material.h"

namespace mesocap::app {

StatusOr<DressedGltfFigures> WriteDressedGltf(const GltfFolder& folder, const DressedMesh& d, const Atlas& atlas,
                                              const SynthMap& atlas_map, const GgxMaterialMaps& sample_maps) {
  // One glTF vertex per (mesh vertex, chart): a vertex on a chart's border has a place in each.
  GltfMeshGeometry g;
  std::map<std::pair<int32_t, int32_t>, uint32_t> index;
  for (int f = 0; f < d.mesh.face_count(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int32_t v = d.mesh.faces[f][k];
      auto [it, inserted] = index.emplace(std::pair{v, atlas.face_chart[f]}, uint32_t(g.position.size() / 3));
      if (inserted) {
        const Eigen::Vector3d &p = d.mesh.positions[v], &n = d.frames.n[v], &s = d.frames.s[v];
        g.position.insert(g.position.end(), {float(p.x()), float(p.y()), float(p.z())});
        g.normal.insert(g.normal.end(), {float(n.x()), float(n.y()), float(n.z())});
        g.tangent.insert(g.tangent.end(), {float(s.x()), float(s.y()), float(s.z()), 1.f});
        const Eigen::Vector2d uv = atlas.corner_uv[f][k] / atlas.size;
        g.uv.insert(g.uv.end(), {float(uv.x()), float(uv.y())});
      }
      g.indices.push_back(it->second);
    }
  GltfMaterialOptions options;
  options.name = "mesocap dressed mesh";
  MESOCAP_RETURN_IF_ERROR(WriteGltfMaterialOnMesh(folder, ApplyMapToMaterial(atlas_map, sample_maps), g, options));
  DressedGltfFigures figures;
  figures.atlas_size = atlas.size, figures.charts = atlas.charts, figures.fill = atlas.fill;
  figures.vertices = int(g.position.size() / 3);
  figures.wide_indices = figures.vertices > 65535;
  return figures;
}

}  // namespace mesocap::app

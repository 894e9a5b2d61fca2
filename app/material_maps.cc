#include "app/material_maps.h"

#include <cmath>

#include "core/directions.h"
#include "core/session_layout.h"

namespace mesocap::app {
namespace fs = std::filesystem;

GgxMaterialMaps ApplyMapToMaterial(const SynthMap& map, const GgxMaterialMaps& maps) {
  GgxMaterialMaps out;
  out.base_color = Image(map.width, map.height, 3);
  out.roughness = Image(map.width, map.height, 1);
  out.metallic = Image(map.width, map.height, 1);
  out.normal = Image(map.width, map.height, 3);
  out.relative_error = Image(map.width, map.height, 1);
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      const Eigen::Vector2i src = map.SourceTexel(x, y);
      const double turn = DegToRad(map.rotation_deg[map.index(x, y)]);
      const float nx = maps.normal.at(src.x(), src.y(), 0), ny = maps.normal.at(src.x(), src.y(), 1);
      out.normal.at(x, y, 0) = float(std::cos(turn) * nx - std::sin(turn) * ny);
      out.normal.at(x, y, 1) = float(std::sin(turn) * nx + std::cos(turn) * ny);
      out.normal.at(x, y, 2) = maps.normal.at(src.x(), src.y(), 2);
      for (int c = 0; c < 3; ++c) out.base_color.at(x, y, c) = maps.base_color.at(src.x(), src.y(), c);
      out.roughness.at(x, y, 0) = maps.roughness.at(src.x(), src.y(), 0);
      out.metallic.at(x, y, 0) = maps.metallic.at(src.x(), src.y(), 0);
      if (!maps.relative_error.empty()) out.relative_error.at(x, y, 0) = maps.relative_error.at(src.x(), src.y(), 0);
    }
  return out;
}

StatusOr<GgxMaterialMaps> ExemplarMaterialMaps(const Exemplar& e, int board, int num_threads, const ProgressFn& progress) {
  if (e.kind == ExemplarKind::kBtf) {
    // The index LoadExemplar read: a BTF folder's, a session's slices', or the file given.
    fs::path index = e.path;
    if (std::error_code ec; fs::is_directory(e.path, ec))
      index = fs::exists(BtfFolder{e.path}.index(), ec) ? BtfFolder{e.path}.index() : SessionLayout(e.path).slices().index();
    GgxFitOptions options;
    options.num_threads = num_threads;
    return FitGgxMaterial(index, options, board, progress);
  }
  GgxMaterialMaps maps;
  maps.roughness = Image(e.width, e.height, 1, 1.f);
  maps.metallic = Image(e.width, e.height, 1, 0.f);
  maps.relative_error = Image(e.width, e.height, 1, 0.f);
  if (e.kind == ExemplarKind::kPtm) {
    PtmNormalsAlbedo na = PtmNormalsAndAlbedo(e.ptm, num_threads);
    maps.base_color = std::move(na.albedo);
    maps.normal = std::move(na.normals);
  } else {
    maps.base_color = Image(e.width, e.height, 3);
    for (int y = 0; y < e.height; ++y)
      for (int x = 0; x < e.width; ++x)
        for (int c = 0; c < 3; ++c) maps.base_color.at(x, y, c) = e.image.at(x, y, std::min(c, e.image.channels() - 1));
    maps.normal = Image(e.width, e.height, 3);
    for (int y = 0; y < e.height; ++y)
      for (int x = 0; x < e.width; ++x) maps.normal.at(x, y, 2) = 1.f;
  }
  return maps;
}

}  // namespace mesocap::app

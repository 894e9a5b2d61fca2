#include "app/decorate_args.h"

#include <CLI/CLI.hpp>

namespace mesocap::app {

CLI::App* AddDecorateOptions(CLI::App& app, DecorateArgs* args) {
  DecorateArgs& a = *args;
  CLI::App* sub = app.add_subcommand(
      "decorate", "Dress a mesh in the material: a per-vertex surface texton map (Tong 2002 §5) or a graphcut quilt on an "
                  "atlas (Zhou 2005 §III), previews, a glTF asset and a report");
  sub->add_option("--mesh", a.mesh, "Mesh file: OBJ, PLY, glTF/GLB or any format Assimp reads (its UVs, if they make an atlas, are the atlas)")->required();
  sub->add_option("--input", a.input, "Exemplar: an image, a BTF folder, a session (its slices), or a .ptm")->required();
  sub->add_option("--out", a.out, "Output folder (must not exist or be empty)")->required();
  sub->add_option("--method", a.method, "Synthesis on the surface: texton (per vertex) or quilt (per atlas texel)")
      ->check(CLI::IsMember({"texton", "quilt"}))
      ->capture_default_str();
  sub->add_option("--field", a.field, "Direction field, JSON {\"points\": [[x,y,z],...], \"directions\": [[dx,dy,dz],...]} "
                                      "(default: a relaxed smooth field)");
  sub->add_option("--seed", a.seed, "Random seed (same seed, same map on any thread count)")->capture_default_str();
  sub->add_option("--texel-size", a.texton.texel_size, "Surface length of one sample texel (0: the mesh's mean edge length)")
      ->capture_default_str();
  sub->add_option("--k", a.texton.k, "k of the k-coherence search (Tong: 11; 1 for \"natural\" textures)")->capture_default_str();
  sub->add_option("--neighbourhood", a.texton.neighbourhood, "N, the N x N template, spaced 2^level texels")->capture_default_str();
  sub->add_option("--passes", a.texton.passes, "Correction passes per level")->capture_default_str();
  sub->add_option("--levels", a.texton.levels, "Mesh pyramid levels (0: as many as the mesh allows, while the sample spans 8 steps of the level's spacing)")->capture_default_str();
  sub->add_option("--patch-radius", a.quilt.patch_radius, "quilt: work patch radius r_w in sample texels (0: 32, or what the sample holds)")
      ->capture_default_str();
  sub->add_option("--textons", a.texton_analysis.textons, "n_t, textons at the finest level")->capture_default_str();
  sub->add_option("--preview-size", a.preview_size, "Preview renders, WxH")->capture_default_str();
  sub->add_option("--atlas-size", a.atlas_size, "Texels a side of the atlas: the glTF asset's textures, and quilt's dense mesh (Zhou: 512 or 1024)")
      ->check(CLI::Range(64, 8192))
      ->capture_default_str();
  sub->add_option("--board", a.board, "Session slices: the board to use (-1: the most head-on)")->capture_default_str();
  sub->add_option("--threads", a.threads, "Threads (-1: all cores)")->capture_default_str();
  sub->add_flag("--no-progress", a.no_progress, "Do not draw progress bars");
  return sub;
}

CLI::App* AddRenderOptions(CLI::App& app, RenderArgs* args) {
  RenderArgs& a = *args;
  CLI::App* sub = app.add_subcommand(
      "render", "Render a dressed mesh (decorate's output) under a light, with cast shadows (Tong 2002 §6 with ray casting)");
  sub->add_option("--map", a.map, "decorate's output folder")->required();
  sub->add_option("--input", a.input, "The exemplar decorate used")->required();
  sub->add_option("--mesh", a.mesh, "The mesh decorate dressed (optional: checked against the map's)");
  sub->add_option("--out", a.out, "Output PNG; with --turntable or --light-sweep, frames are OUT-stem_0000.png, ...")->required();
  auto* light = sub->add_option("--light", a.light, "Direction toward a distant light, x,y,z in the mesh's frame")->delimiter(',')->expected(3);
  auto* light_pos = sub->add_option("--light-pos", a.light_pos, "A point light's position, x,y,z")->delimiter(',')->expected(3);
  light->excludes(light_pos);
  sub->add_option("--view", a.view, "Camera position x,y,z, looking at the mesh's centre (default: framing the whole mesh)")
      ->delimiter(',')
      ->expected(3);
  sub->add_option("--size", a.size, "Image size, WxH")->capture_default_str();
  sub->add_option("--turntable", a.turntable, "Frames of the camera circling the mesh (about its up axis, y)")->capture_default_str();
  sub->add_option("--light-sweep", a.light_sweep, "Frames of the light circling the mesh at 45 deg elevation")->capture_default_str();
  sub->add_option("--exposure", a.exposure, "Scale on the linear values before display")->capture_default_str();
  sub->add_option("--board", a.board, "Session slices: the board to use (-1: the most head-on)")->capture_default_str();
  sub->add_option("--threads", a.threads, "Threads (-1: all cores)")->capture_default_str();
  sub->add_flag("--no-progress", a.no_progress, "Do not draw progress bars");
  return sub;
}

}  // namespace mesocap::app

// mesocap decorate and render: dressing a mesh in the material (mesh/) and rendering it. The
// options, parsed by the front executable (app/main.cc), and the runs (app/decorate_cmd.cc,
// app/render_cmd.cc), which the front reaches through the commands module once one is chosen.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "mesh/surface_quilt.h"
#include "mesh/surface_textons.h"
#include "synth/texton_analysis.h"

namespace CLI {
class App;
}

namespace mesocap::app {

struct DecorateArgs {
  std::filesystem::path mesh, input, field, out;
  std::string method = "texton";
  std::string preview_size = "512x512";
  int atlas_size = 512;
  SurfaceTextonOptions texton;
  SurfaceQuiltOptions quilt;
  TextonAnalysisOptions texton_analysis;
  int board = -1;
  uint32_t seed = 1;
  int threads = -1;
  bool no_progress = false;
};

struct RenderArgs {
  std::filesystem::path mesh, map, input, out;
  std::vector<double> light, light_pos, view;
  std::string size = "1024x1024";
  int turntable = 0, light_sweep = 0;
  double exposure = 1.0;
  int board = -1;
  int threads = -1;
  bool no_progress = false;
};

CLI::App* AddDecorateOptions(CLI::App& app, DecorateArgs* args);
int RunDecorate(DecorateArgs& a);
CLI::App* AddRenderOptions(CLI::App& app, RenderArgs* args);
int RunRender(RenderArgs& a);

}  // namespace mesocap::app

// mesocap simulate: render a virtual capture session, or one true BTF slice (--true-btf).
#include <cstdio>

#include "app/commands.h"
#include "capture/btf_render.h"
#include "capture/simulate.h"
#include "core/image_io.h"

namespace mesocap::app {
namespace {

struct SimulateArgs {
  SimulateOptions session;
  bool true_btf = false;
  TrueBtfRequest btf;
  bool no_progress = false;
};

int RunTrueBtf(const SimulateArgs& a) {
  auto material = Material::Create(a.session.rig.material);
  if (!material.ok()) return Fail("simulate", material.status().message(), kExitUsage);
  const TrueBtfRequest& r = a.btf;
  if (r.theta_i_deg < 0 || r.theta_i_deg >= 90 || r.theta_o_deg < 0 || r.theta_o_deg >= 90)
    return Fail("simulate", "--theta-i and --theta-o must be in [0, 90) degrees", kExitUsage);
  if (r.size < 8 || r.size > 8192) return Fail("simulate", "--size must be 8..8192", kExitUsage);
  if (a.session.out.extension() != ".exr") return Fail("simulate", "--true-btf writes OpenEXR: --out must end in .exr", kExitUsage);
  const Image slice = RenderTrueBtfSlice(*material, r);
  ImageWriteOptions w;
  w.format = PixelFormat::kFloat;
  w.attributes["mesocap:material"] = a.session.rig.material;
  w.attributes["mesocap:theta_i_deg"] = float(r.theta_i_deg);
  w.attributes["mesocap:phi_i_deg"] = float(r.phi_i_deg);
  w.attributes["mesocap:theta_o_deg"] = float(r.theta_o_deg);
  w.attributes["mesocap:phi_o_deg"] = float(r.phi_o_deg);
  w.attributes["mesocap:patch_m"] = float(r.patch_m);
  w.attributes["mesocap:quantity"] = std::string("BTF: radiance per unit perpendicular irradiance (includes cos theta_i)");
  if (Status st = WriteImage(a.session.out, slice, w); !st.ok()) return Fail("simulate", st.message());
  std::printf("true BTF slice %s (%dx%d) -> %s\n", a.session.rig.material.c_str(), r.size, r.size,
              a.session.out.string().c_str());
  return kExitOk;
}

}  // namespace

Command SimulateCommand() {
  auto args = std::make_shared<SimulateArgs>();
  Command c;
  c.name = "simulate";
  c.setup = [args](CLI::App& app) {
    CLI::App* sub = app.add_subcommand("simulate", "Render a virtual capture session with known ground truth");
    SimulateOptions& o = args->session;
    sub->add_option("--out", o.out, "Output session folder (must not exist or be empty); with --true-btf an .exr file")->required();
    std::string names;
    for (const auto& m : MaterialCatalog()) names += (names.empty() ? "" : ", ") + m.name;
    sub->add_option("--material", o.rig.material, "Material: " + names)->capture_default_str();
    sub->add_option("--shots", o.rig.shots, "Flash shots")->capture_default_str();
    sub->add_option("--calib-shots", o.rig.calib_shots, "Checkerboard shots")->capture_default_str();
    sub->add_option("--seed", o.rig.seed, "Random seed: same seed, same bytes")->capture_default_str();
    sub->add_option("--width", o.rig.width, "Image width in pixels")->capture_default_str();
    sub->add_option("--height", o.rig.height, "Image height in pixels")->capture_default_str();
    sub->add_option("--format", o.image_format, "Shot files: jpg (8-bit sRGB), png (16-bit linear), exr (float linear)")
        ->capture_default_str();
    sub->add_option("--samples-per-axis", o.render.samples_per_axis, "Anti-aliasing samples per pixel axis")
        ->capture_default_str();
    sub->add_option("--threads", o.render.num_threads, "Threads (-1: all cores)")->capture_default_str();
    sub->add_flag("--no-progress", args->no_progress, "Do not draw a progress bar");
    sub->add_flag("--true-btf", args->true_btf, "Render one true BTF slice of --material to --out (.exr)");
    sub->add_option("--theta-i", args->btf.theta_i_deg, "True BTF: light zenith angle, degrees");
    sub->add_option("--phi-i", args->btf.phi_i_deg, "True BTF: light azimuth, degrees");
    sub->add_option("--theta-o", args->btf.theta_o_deg, "True BTF: view zenith angle, degrees");
    sub->add_option("--phi-o", args->btf.phi_o_deg, "True BTF: view azimuth, degrees");
    sub->add_option("--size", args->btf.size, "True BTF: texels per side")->capture_default_str();
  };
  c.run = [args]() {
    if (args->true_btf) return RunTrueBtf(*args);
    if (std::string why = args->session.Check(); !why.empty()) return Fail("simulate", why, kExitUsage);
    ProgressBar bar("simulate", !args->no_progress);
    auto report = SimulateSession(args->session, bar.AsCallback());
    if (!report.ok()) return Fail("simulate", report.status().message());
    std::printf("%s\n", report->Brief().c_str());
    return kExitOk;
  };
  return c;
}

}  // namespace mesocap::app

// mesocap simulate: render a virtual capture session, or one true BTF slice (--true-btf).
#include "app/simulate_args.h"

#include <cstdio>

#include "app/commands.h"
#include "capture/btf_render.h"
#include "capture/simulate.h"
#include "core/image_io.h"
#include "core/progress.h"
#include "core/slice_attributes.h"

namespace mesocap::app {
namespace {

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
  SetSliceAngles(&w.attributes, r.theta_i_deg, r.phi_i_deg, r.theta_o_deg, r.phi_o_deg);
  w.attributes["mesocap:patch_m"] = float(r.patch_m);
  w.attributes["mesocap:quantity"] = kBtfSliceQuantity;
  if (Status st = WriteImage(a.session.out, slice, w); !st.ok()) return Fail("simulate", st);
  std::printf("true BTF slice %s (%dx%d) -> %s\n", a.session.rig.material.c_str(), r.size, r.size,
              a.session.out.string().c_str());
  return kExitOk;
}

}  // namespace

int RunSimulate(SimulateArgs& a) {
  if (a.true_btf) return RunTrueBtf(a);
  if (std::string why = a.session.Check(); !why.empty()) return Fail("simulate", why, kExitUsage);
  ProgressBar bar("simulate", !a.no_progress);
  auto report = SimulateSession(a.session, bar.AsCallback());
  if (!report.ok()) return Fail("simulate", report.status());
  std::printf("%s\n", report->Brief().c_str());
  return kExitOk;
}
}  // namespace mesocap::app

#include "capture/true_btf_folder.h"

#include <cstdio>

#include "capture/btf_render.h"
#include "core/atomic_file.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "core/json.h"
#include "core/provenance.h"
#include "core/slice_attributes.h"
#include "core/session_layout.h"

namespace mesocap {

Status WriteTrueBtfFolder(const Material& material, const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& pairs,
                          const TrueBtfFolderOptions& options, const std::filesystem::path& out_path) {
  auto staged = StagingFolder::Begin(out_path);  // removed on any early return
  if (!staged.ok()) return staged.status();
  const std::filesystem::path staging = staged->path();
  const BtfFolder folder{staging};
  std::error_code ec;
  std::filesystem::create_directories(folder.slices(), ec);
  if (ec) return Status::Error(staging.string() + ": cannot create: " + ec.message());
  Json entries = Json::array();
  for (size_t k = 0; k < pairs.size(); ++k) {
    TrueBtfRequest request = TrueBtfRequestFor(pairs[k].first, pairs[k].second, options.size, options.samples_per_axis);
    request.patch_m = options.patch_m;
    const Image slice = RenderTrueBtfSlice(material, request, options.num_threads);
    char file_name[96];
    std::snprintf(file_name, sizeof file_name, "%04zu_ti%04.1f_pi%05.1f_to%04.1f_po%05.1f.exr", k, request.theta_i_deg,
                  request.phi_i_deg, request.theta_o_deg, request.phi_o_deg);
    const std::string name = BtfFolder::SliceEntry(file_name);
    ImageWriteOptions w;
    w.format = PixelFormat::kFloat;
    SetSliceAngles(&w.attributes, request.theta_i_deg, request.phi_i_deg, request.theta_o_deg, request.phi_o_deg);
    w.attributes["mesocap:patch_m"] = float(options.patch_m);
    w.attributes["mesocap:material"] = material.name();
    w.attributes["mesocap:method"] = std::string("true BTF (virtual rig)");
    if (Status st = WriteImage(staging / name, slice, w); !st.ok()) return st;
    entries.push_back({{"file", name}, {"theta_i_deg", request.theta_i_deg}, {"phi_i_deg", request.phi_i_deg},
                       {"theta_o_deg", request.theta_o_deg}, {"phi_o_deg", request.phi_o_deg}});
  }
  Json index = {{"format", "mesocap-btf"}, {"width", options.size}, {"height", options.size}, {"material", material.name()},
                {"patch_m", options.patch_m}, {"slices", entries}};
  index["provenance"] = MakeProvenance({{"size", options.size}, {"samples_per_axis", options.samples_per_axis}});
  if (Status st = WriteJsonFile(folder.index(), index); !st.ok()) return st;
  return staged->Publish();
}

}  // namespace mesocap

#include "app/synth_output.h"

#include <chrono>
#include <cstdio>
#include <sstream>

#include "core/atomic_file.h"
#include "core/directions.h"
#include "core/image_io.h"
#include "core/provenance.h"
#include "core/resource_usage.h"
#include "core/slice_attributes.h"
#include "export/previews.h"
#include "formats/ptm_file.h"
#include "synth/map_apply.h"
#include "synth/synth_quality.h"

namespace mesocap::app {
namespace fs = std::filesystem;

bool ParseSize(const std::string& text, int* width, int* height) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  const int n = std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra);
  if (n == 1) h = w;
  else if (n != 3 || (x != 'x' && x != 'X')) return false;
  if (w < 1 || h < 1 || w > 32768 || h > 32768) return false;
  *width = w, *height = h;
  return true;
}

bool ParseSliceList(const std::string& text, int count, std::vector<int>* slices) {
  slices->clear();
  if (text.empty() || text == "all") return true;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) {
    size_t used = 0;
    int k = -1;
    try {
      k = std::stoi(item, &used);
    } catch (...) {
      return false;
    }
    if (used != item.size() || k < 0 || k >= count) return false;
    slices->push_back(k);
  }
  return !slices->empty();
}

StatusOr<Image> ReadMask(const fs::path& path) {
  ImageReadOptions options;
  options.linearize = false;
  auto image = ReadImage(path, options);
  if (!image.ok()) return image.status();
  Image mask(image->width(), image->height(), 1);
  for (size_t t = 0; t < mask.pixel_count(); ++t) mask.data()[t] = image->data()[t * image->channels()] > 0.5f ? 1.f : 0.f;
  return mask;
}

namespace {

// Three slices to show: the most head-on view under three well-separated lights.
std::vector<int> PreviewSlices(const Exemplar& e) {
  std::vector<int> order(e.slices.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = int(k);
  double best_view = 1e9;
  for (const auto& s : e.slices) best_view = std::min(best_view, s.theta_o_deg);
  std::vector<int> chosen;
  for (int k : order) {
    if (e.slices[k].theta_o_deg > best_view + 1) continue;
    bool far = true;
    for (int c : chosen) far &= AngleBetweenDeg(e.slices[c].light, e.slices[k].light) > 20;
    if (far) chosen.push_back(k);
    if (chosen.size() == 3) break;
  }
  return chosen;
}

Json SeamJson(const SynthMap& map, const Image& output, const Image& sample, const std::string& label) {
  const SeamMeasure s = MeasureSeams(map, output, sample);
  return {{"image", label}, {"mean_cut_step", s.mean_cut_step}, {"cut_pairs", s.cut_pairs},
          {"sample_neighbour_step", s.mean_sample_step}, {"ratio", s.ratio()}};
}

}  // namespace

Json ExemplarReport(const Exemplar& e) {
  return {{"path", e.path.string()}, {"kind", ExemplarKindToString(e.kind)}, {"width", e.width}, {"height", e.height},
          {"slices", e.slices.size()}, {"features", e.features.channels()}, {"svd_energy_kept", e.svd_energy_kept}};
}

StatusOr<std::vector<Json>> WriteSynthesizedSlices(const SynthMap& map, const Exemplar& e, const std::vector<int>& slices,
                                                   const fs::path& folder, int num_threads, const ProgressFn& progress,
                                                   const std::function<void(int k, const Image& slice)>& on_slice) {
  std::error_code ec;
  fs::create_directories(BtfFolder{folder}.slices(), ec);
  if (ec) return Status::Error(folder.string() + ": cannot create: " + ec.message());
  std::vector<Json> entries(e.slices.size());
  std::mutex mutex;
  ApplyOptions apply;
  apply.num_threads = num_threads;
  Status st = ApplyMapToBtf(map, e, slices, [&](int k, const Image& slice) -> Status {
    const ExemplarSlice& s = e.slices[k];
    const std::string name = BtfFolder::SliceEntry(s.file.filename().string());
    ImageWriteOptions w;
    w.format = PixelFormat::kHalf;
    SetSliceAngles(&w.attributes, s.theta_i_deg, s.phi_i_deg, s.theta_o_deg, s.phi_o_deg);
    w.attributes["mesocap:method"] = "synthesized (" + map.method + ")";
    MESOCAP_RETURN_IF_ERROR(WriteImage(folder / name, slice, w));
    if (on_slice) on_slice(k, slice);
    std::lock_guard<std::mutex> lock(mutex);
    entries[k] = {{"file", name}, {"theta_i_deg", s.theta_i_deg}, {"phi_i_deg", s.phi_i_deg},
                  {"theta_o_deg", s.theta_o_deg}, {"phi_o_deg", s.phi_o_deg}};
    return Status::Ok();
  }, apply, progress);
  if (!st.ok()) return st;
  std::vector<Json> list;
  for (int k : slices) list.push_back(entries[k]);
  return list;
}

Status WriteSynthesisOutputs(const SynthMap& map, const Exemplar& e, SynthOutputRequest request, const ProgressFn& progress) {
  const auto start = std::chrono::steady_clock::now();
  auto staged = StagingFolder::Begin(request.out);
  if (!staged.ok()) return staged.status();
  const fs::path staging = staged->path();
  const SynthFolder out{staging};
  // On any failure below, `staged` removes the staging folder as it goes out of scope.
  if (Status st = WriteSynthMap(out.map(), map); !st.ok()) return st;
  if (Status st = WriteImage(out.patches(), PatchPicture(map)); !st.ok()) return st;
  if (request.write_extra) MESOCAP_RETURN_IF_ERROR(request.write_extra(staging));

  Json seams = Json::array();
  std::vector<Image> previews;
  std::vector<fs::path> preview_files;
  const auto preview_name = [&] { return preview_files.back().filename().string(); };
  if (e.kind == ExemplarKind::kImage) {
    const Image synthesized = ApplyMapToImage(map, e.image);
    ImageWriteOptions exr;
    exr.format = PixelFormat::kFloat;
    if (Status st = WriteImage(out.image(), synthesized, exr); !st.ok()) return st;
    previews = {synthesized};
    preview_files = {out.preview()};
    seams.push_back(SeamJson(map, synthesized, e.image, "image"));
  } else if (e.kind == ExemplarKind::kPtm) {
    const Ptm synthesized = ApplyMapToPtm(map, e.ptm);
    if (Status st = WritePtmFile(out.ptm(), synthesized); !st.ok()) return st;
    int k = 0;
    for (const Eigen::Vector3d& light : {Eigen::Vector3d(0, 0, 1), DirectionFromAnglesDeg(45, 0), DirectionFromAnglesDeg(60, 135)}) {
      previews.push_back(RelightPtm(synthesized, light));
      preview_files.push_back(out.preview_light(++k));
      seams.push_back(SeamJson(map, previews.back(), RelightPtm(e.ptm, light), preview_name()));
    }
  } else {
    std::vector<int> slices = request.slices;
    if (slices.empty())
      for (int k = 0; k < int(e.slices.size()); ++k) slices.push_back(k);
    const std::vector<int> shown = PreviewSlices(e);
    std::vector<Image> shown_images(shown.size());
    std::mutex mutex;
    const auto keep_shown = [&](int k, const Image& slice) {
      std::lock_guard<std::mutex> lock(mutex);
      for (size_t i = 0; i < shown.size(); ++i)
        if (shown[i] == k) shown_images[i] = slice;
    };
    auto list = request.take_slices
                    ? request.take_slices(staging)
                    : WriteSynthesizedSlices(map, e, slices, staging, request.num_threads, progress, keep_shown);
    if (!list.ok()) return list.status();
    Json index = {{"format", "mesocap-btf"}, {"width", map.width}, {"height", map.height}, {"method", map.method},
                  {"exemplar", e.path.string()}, {"slices", *list}};
    if (Status s2 = WriteJsonFile(out.btf().index(), index); !s2.ok()) return s2;
    auto lookup = SliceDirectionLookup::Create(e.slices);
    if (!lookup.ok()) return lookup.status();
    for (size_t i = 0; i < shown.size(); ++i) {
      if (shown_images[i].empty()) {  // not among the requested slices: make it for the preview
        auto made = SynthesizedSlice(map, *lookup, e.slices[shown[i]], [&](int k) { return e.ReadSlice(k); });
        if (!made.ok()) return made.status();
        shown_images[i] = std::move(*made);
      }
      previews.push_back(shown_images[i]);
      preview_files.push_back(out.preview_light(int(i) + 1));
      auto sample = e.ReadSlice(shown[i]);
      if (!sample.ok()) return sample.status();
      Json j = SeamJson(map, shown_images[i], *sample, preview_name());
      j["slice"] = e.slices[shown[i]].file.filename().string();
      seams.push_back(j);
    }
  }
  const std::vector<Image> exposed = ExposeTogether(previews);
  for (size_t i = 0; i < exposed.size(); ++i)
    if (Status st = WriteImage(preview_files[i], exposed[i]); !st.ok()) return st;

  Json& report = request.report;
  report["exemplar"] = request.exemplar_report.is_null() ? ExemplarReport(e) : request.exemplar_report;
  report["output"] = {{"width", map.width}, {"height", map.height}};
  report["seams"] = seams;
  report["seconds_writing"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report["memory_peak_mib"] = PeakMemoryMiB();
  report["provenance"] = MakeProvenance(report.value("parameters", Json::object()));
  if (Status st = WriteJsonFile(out.report(), report); !st.ok()) return st;
  if (Status st = staged->Publish(request.replace); !st.ok()) return st;
  return Status::Ok();
}

StatusOr<SynthReportSummary> ReadSynthReportSummary(const SynthFolder& folder) {
  return ReadJsonRecord(folder.report(), [](const Json& json) {
    SynthReportSummary summary;
    summary.method = JsonString(JsonField(json, "", "method"), "method");
    const Json& output = JsonField(json, "", "output");
    summary.width = JsonInteger(JsonField(output, "output", "width"), "output.width", 1, 1 << 20);
    summary.height = JsonInteger(JsonField(output, "output", "height"), "output.height", 1, 1 << 20);
    if (summary.method == "roller" && json.contains("derived")) {  // synth-apply of a roller map: none
      const Json& derived = JsonField(json, "", "derived");
      summary.tile_width = JsonInteger(JsonField(derived, "derived", "tile_width"), "derived.tile_width", 0, 1 << 20);
      summary.tile_height = JsonInteger(JsonField(derived, "derived", "tile_height"), "derived.tile_height", 0, 1 << 20);
    }
    return summary;
  });
}

}  // namespace mesocap::app

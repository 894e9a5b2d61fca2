#include "app/ggx_shards.h"

#include <algorithm>
#include <cmath>

#include "app/shard_parts.h"
#include "core/image_io.h"
#include "core/median.h"
#include "core/progress.h"
#include "core/session_layout.h"
#include "core/text_format.h"

namespace mesocap::app {

namespace fs = std::filesystem;

namespace {

constexpr const char* kStage = "export";

// The band's maps in its part, as float OpenEXR (exact).
struct BandMap {
  const char* file;
  Image GgxMaterialMaps::*map;
};
constexpr BandMap kBandMaps[] = {{"base_color.exr", &GgxMaterialMaps::base_color},
                                 {"roughness.exr", &GgxMaterialMaps::roughness},
                                 {"metallic.exr", &GgxMaterialMaps::metallic},
                                 {"normal.exr", &GgxMaterialMaps::normal},
                                 {"relative_error.exr", &GgxMaterialMaps::relative_error}};

StatusOr<int> BtfRows(const fs::path& session) {
  const fs::path index = SessionLayout(session).btf().index();
  auto json = ReadJsonFile(index);
  if (!json.ok()) return json.status();
  const Json rows = json->value("height", Json());
  if (!rows.is_number_integer() || rows.get<int>() < 1) return Status::Error(index.string() + ": no height");
  return rows.get<int>();
}

}  // namespace

StatusOr<StageSummary> RunGgxShard(const fs::path& session, const Shard& shard, const std::string& key, int num_threads,
                                   bool progress, bool* done_before) {
  const ShardsFolder folder = SessionLayout(session).shards(kStage, key);
  auto rows = BtfRows(session);
  if (!rows.ok()) return rows.status();
  const auto [first, last] = shard.Range(size_t(*rows));
  StageSummary summary;
  const auto fill = [&, first = first, last = last](PartWriter& part) -> Status {
    GgxFitOptions options;
    options.num_threads = num_threads;
    ProgressBar bar("GGX fit " + shard.Name(), progress);
    auto maps = FitGgxMaterialRows(SessionLayout(session).btf().index(), options, {int(first), int(last)}, -1,
                                   bar.AsCallback());
    if (!maps.ok()) return maps.status();
    const size_t texels = maps->base_color.pixel_count();
    if (texels > 0)
      for (const BandMap& m : kBandMaps)
        MESOCAP_RETURN_IF_ERROR(WriteImage(part.folder() / m.file, (*maps).*m.map, {.format = PixelFormat::kFloat}));
    summary.brief = Format("shard %s: GGX fit of rows %zu..%zu of %d", shard.Name().c_str(), first, last, *rows);
    // Counts back from the means (exact: integers below 2^53), so the merge's means are the whole fit's.
    return part.Publish({{"rows", {first, last}},
                         {"slices_used", maps->slices_used},
                         {"iterations", std::llround(maps->mean_iterations * double(texels))},
                         {"evaluations", std::llround(maps->mean_evaluations * double(texels))},
                         {"seconds", maps->seconds}});
  };
  MESOCAP_RETURN_IF_ERROR(RunShardPart(folder, kStage, key, shard, fill, done_before));
  if (*done_before) summary.brief = "shard " + shard.Name() + ": done before";
  return summary;
}

StatusOr<GgxMaterialMaps> MergeGgxShards(const fs::path& session, int count, const std::string& key,
                                         const std::string& make_command) {
  const SessionLayout layout(session);
  const ShardsFolder folder = layout.shards(kStage, key);
  auto parts = ReadShardParts(folder, kStage, key, count, make_command);
  if (!parts.ok()) return parts.status();
  auto rows = BtfRows(session);
  if (!rows.ok()) return rows.status();
  GgxMaterialMaps maps;
  long long iterations = 0, evaluations = 0;
  for (int k = 0; k < count; ++k) {
    const Json& part = (*parts)[size_t(k)];
    const Json band = part.value("rows", Json::array());
    const Shard shard{k + 1, count};
    const auto [first, last] = shard.Range(size_t(*rows));
    if (band != Json{first, last}) return Status::Error(folder.part(k + 1, count).string() + ": not the rows of its shard");
    maps.slices_used = part.value("slices_used", 0);
    iterations += part.value("iterations", 0LL), evaluations += part.value("evaluations", 0LL);
    maps.seconds += part.value("seconds", 0.0);
    if (first == last) continue;
    for (const BandMap& m : kBandMaps) {
      auto image = ReadImage(folder.part(k + 1, count) / m.file, {.linearize = false});
      if (!image.ok()) return image.status();
      Image& whole = maps.*m.map;
      if (whole.empty()) whole = Image(image->width(), *rows, image->channels());
      if (image->width() != whole.width() || image->channels() != whole.channels() ||
          image->height() != int(last - first))
        return Status::Error(folder.part(k + 1, count).string() + "/" + m.file + ": not the size of its band");
      std::copy(image->data(), image->data() + image->size(), whole.row(int(first)));
    }
  }
  const size_t texels = maps.relative_error.pixel_count();
  if (texels == 0) return Status::Error(folder.root.string() + ": the shards hold no texels");
  maps.median_relative_error =
      UpperMedian(std::vector<float>(maps.relative_error.data(), maps.relative_error.data() + texels));
  maps.mean_iterations = double(iterations) / double(texels);
  maps.mean_evaluations = double(evaluations) / double(texels);
  return maps;  // the parts stay until the export stage made with these maps is recorded
}

}  // namespace mesocap::app

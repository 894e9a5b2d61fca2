#include "app/ggx_shards.h"

#include <algorithm>
#include <cmath>
#include <fstream>

#include "app/shard_parts.h"
#include "core/binary_record.h"
#include "core/median.h"
#include "core/progress.h"
#include "core/session_layout.h"
#include "core/text_format.h"

namespace mesocap::app {

namespace fs = std::filesystem;

namespace {

constexpr const char* kStage = "export";

// The band's maps in its part as one binary record of floats (exact; and no image codec to load,
// which would cost a small shard more than its fit).
constexpr const char* kBandRecord = "band.bin";
constexpr const char* kBandFormat = "mesocap-ggx-band 1";
constexpr Image GgxMaterialMaps::*kBandMaps[] = {&GgxMaterialMaps::base_color, &GgxMaterialMaps::roughness,
                                                 &GgxMaterialMaps::metallic, &GgxMaterialMaps::normal,
                                                 &GgxMaterialMaps::relative_error};

Status WriteBand(const fs::path& file, const GgxMaterialMaps& maps) {
  BinaryRecordWriter w(kBandFormat);
  for (const auto map : kBandMaps) {
    const Image& image = maps.*map;
    w.I32(image.width()), w.I32(image.height()), w.I32(image.channels());
    w.Floats({image.data(), image.size()});
  }
  return w.WriteTo(file);
}

StatusOr<GgxMaterialMaps> ReadBand(const fs::path& file) {
  auto reader = BinaryRecordReader::Open(file, kBandFormat);
  if (!reader.ok()) return reader.status();
  GgxMaterialMaps maps;
  for (const auto map : kBandMaps) {
    const int width = reader->I32(), height = reader->I32(), channels = reader->I32();
    const std::vector<float> pixels = reader->Floats();
    if (width < 0 || height < 0 || channels < 1 || channels > 4 ||
        pixels.size() != size_t(width) * size_t(height) * size_t(channels)) {
      reader->MarkBroken("a map's size does not match its pixels");
      break;
    }
    maps.*map = Image(width, height, channels);
    std::copy(pixels.begin(), pixels.end(), (maps.*map).data());
  }
  MESOCAP_RETURN_IF_ERROR(reader->Finish());
  return maps;
}

StatusOr<int> BtfRows(const fs::path& session) {
  const fs::path index = SessionLayout(session).btf().index();
  auto json = ReadJsonFile(index);
  if (!json.ok()) return json.status();
  const Json rows = json->value("height", Json());
  if (!rows.is_number_integer() || rows.get<int>() < 1) return Status::Error(index.string() + ": no height");
  return rows.get<int>();
}

// The fit's observations of every texel, read from the slices once (by the first shard) and kept
// in shared/: their directions in a JSON record, the texel-major table as raw floats, so each
// shard reads only its band's bytes and no shard decodes a slice again.
constexpr const char* kObservationsRecord = "ggx_observations.json";
constexpr const char* kObservationsTable = "ggx_observations.f32";

Json DirectionsJson(const std::vector<Eigen::Vector3d>& directions) {
  Json list = Json::array();
  for (const Eigen::Vector3d& d : directions) list.push_back({d.x(), d.y(), d.z()});
  return list;
}

Status WriteObservations(const fs::path& folder, const GgxObservations& all) {
  MESOCAP_RETURN_IF_ERROR(WriteJsonFile(folder / kObservationsRecord, {{"width", all.width}, {"height", all.height},
                                                                       {"lights", DirectionsJson(all.lights)},
                                                                       {"views", DirectionsJson(all.views)}}));
  std::ofstream table(folder / kObservationsTable, std::ios::binary);
  table.write(reinterpret_cast<const char*>(all.table.data()), std::streamsize(all.table.size() * sizeof(float)));
  if (!table.flush()) return Status::Error((folder / kObservationsTable).string() + ": cannot write");
  return Status::Ok();
}

// Rows [first, last) of the shared observations.
StatusOr<GgxObservations> ReadObservationRows(const fs::path& folder, size_t first, size_t last) {
  auto record = ReadJsonRecord(folder / kObservationsRecord, [](const Json& j) {
    GgxObservations o;
    o.width = JsonInteger(JsonField(j, "", "width"), "width", 1, 1 << 16);
    o.height = JsonInteger(JsonField(j, "", "height"), "height", 1, 1 << 16);
    for (const char* field : {"lights", "views"})
      for (const Json& d : JsonField(j, "", field)) {
        if (!d.is_array() || d.size() != 3) throw JsonFieldError(std::string(field) + ": not a direction");
        (field[0] == 'l' ? o.lights : o.views).emplace_back(d[0].get<double>(), d[1].get<double>(), d[2].get<double>());
      }
    return o;
  });
  if (!record.ok()) return record.status();
  GgxObservations band = std::move(*record);
  const size_t row_floats = size_t(band.width) * band.lights.size() * 3;
  const fs::path table = folder / kObservationsTable;
  std::error_code ec;
  if (band.lights.size() != band.views.size() || last > size_t(band.height) ||
      fs::file_size(table, ec) != row_floats * band.height * sizeof(float))
    return Status::Error(table.string() + ": not the size its record gives");
  band.height = int(last - first);
  band.table.resize(row_floats * band.height);
  std::ifstream in(table, std::ios::binary);
  in.seekg(std::streamoff(row_floats * first * sizeof(float)));
  in.read(reinterpret_cast<char*>(band.table.data()), std::streamsize(band.table.size() * sizeof(float)));
  if (!in) return Status::Error(table.string() + ": cannot read rows " + std::to_string(first) + ".." + std::to_string(last));
  return band;
}

// The shard's band of the shared observations; `*computed`: this shard read the slices.
StatusOr<GgxObservations> BandObservations(const fs::path& session, const ShardsFolder& folder, const GgxFitOptions& options,
                                           size_t first, size_t last, bool progress, bool* computed) {
  *computed = false;
  const auto compute = [&](const fs::path& staging) -> StatusOr<GgxObservations> {
    *computed = true;
    ProgressBar bar("GGX observations", progress);
    auto all = ReadGgxObservations(SessionLayout(session).btf().index(), options, {}, -1, bar.AsCallback());
    if (!all.ok()) return all.status();
    MESOCAP_RETURN_IF_ERROR(WriteObservations(staging, *all));
    const size_t row_floats = size_t(all->width) * all->lights.size() * 3;
    GgxObservations band{all->width, int(last - first), std::move(all->lights), std::move(all->views), {}};
    band.table.assign(all->table.begin() + long(row_floats * first), all->table.begin() + long(row_floats * last));
    return band;
  };
  return WithSharedFolder<GgxObservations>(folder, compute,
                                           [&] { return ReadObservationRows(folder.shared(), first, last); });
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
    bool computed = false;
    auto band = BandObservations(session, folder, options, first, last, progress, &computed);
    if (!band.ok()) return band.status();
    ProgressBar bar("GGX fit " + shard.Name(), progress);
    auto maps = FitGgxObservations(*band, options, bar.AsCallback());
    if (!maps.ok()) return maps.status();
    const size_t texels = maps->base_color.pixel_count();
    MESOCAP_RETURN_IF_ERROR(WriteBand(part.folder() / kBandRecord, *maps));
    summary.brief = Format("shard %s: GGX fit of rows %zu..%zu of %d, the slices %s", shard.Name().c_str(), first, last,
                           *rows, computed ? "read (shared with the other shards)" : "read by the first shard");
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
    const fs::path file = folder.part(k + 1, count) / kBandRecord;
    auto band_maps = ReadBand(file);
    if (!band_maps.ok()) return band_maps.status();
    for (const auto map : kBandMaps) {
      const Image& image = (*band_maps).*map;
      Image& whole = maps.*map;
      if (whole.empty()) whole = Image(image.width(), *rows, image.channels());
      if (image.width() != whole.width() || image.channels() != whole.channels() || image.height() != int(last - first))
        return Status::Error(file.string() + ": not the size of its band");
      std::copy(image.data(), image.data() + image.size(), whole.row(int(first)));
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

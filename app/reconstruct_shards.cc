#include "app/reconstruct_shards.h"

#include <chrono>

#include "app/btf_folder.h"
#include "app/shard_parts.h"
#include "core/atomic_file.h"
#include "core/progress.h"
#include "core/text_format.h"
#include "reconstruct/statistics_record.h"

namespace mesocap::app {

namespace fs = std::filesystem;

namespace {

constexpr const char* kStage = "reconstruct";

// The statistics every shard shares: computed from the slices by the first shard, read by the rest.
StatusOr<StatisticsRecord> SharedStatistics(const fs::path& session, const SliceSetOptions& options,
                                            const ShardsFolder& folder, bool progress, bool* computed) {
  auto index = ReconstructStageIndex(session);
  if (!index.ok()) return index.status();
  *computed = false;
  const auto compute = [&](const fs::path& staging) -> StatusOr<StatisticsRecord> {
    *computed = true;
    const auto start = std::chrono::steady_clock::now();
    ProgressBar bar("statistics", progress);
    StatisticsRecord record;
    auto inputs = LoadStatisticalBtfInputs(*index, options, &record.report, bar.AsCallback());
    if (!inputs.ok()) return inputs.status();
    record.inputs = std::move(*inputs);
    record.report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    MESOCAP_RETURN_IF_ERROR(WriteStatisticsRecord(staging / ShardsFolder::statistics_name(), record));
    return record;
  };
  const auto read = [&] { return ReadStatisticsRecord(folder.shared() / ShardsFolder::statistics_name(), options.btf); };
  return WithSharedFolder<StatisticsRecord>(folder, compute, read);
}

}  // namespace

StatusOr<StageSummary> RunReconstructShard(const fs::path& session, const ReconstructStageOptions& options,
                                           const Shard& shard, const std::string& key, bool progress, bool* done_before) {
  auto slice_options = options.SliceOptions();
  if (!slice_options.ok()) return slice_options.status();
  const ShardsFolder folder = SessionLayout(session).shards(kStage, key);
  const std::vector<DirectionPair> all = GridPairs(options.grid);
  const auto [first, last] = shard.Range(all.size());
  const std::vector<DirectionPair> pairs(all.begin() + long(first), all.begin() + long(last));
  StageSummary summary;
  const auto fill = [&](PartWriter& part) -> Status {
    bool computed = false;
    auto record = SharedStatistics(session, *slice_options, folder, progress, &computed);
    if (!record.ok()) return record.status();
    const SliceSetReport loaded = record->report;
    auto btf = CreateStatisticalBtf(std::move(record->inputs));
    if (!btf.ok()) return btf.status();
    ProgressBar bar("reconstruct " + shard.Name(), progress);
    auto reconstructed = ReconstructPairs(*btf, pairs, options.pixel_only, slice_options->btf.num_threads,
                                          part.folder(), bar.AsCallback());
    if (!reconstructed.ok()) return reconstructed.status();
    summary.brief = Format("shard %s: %zu of %zu slices, %.1f ms per slice, statistics %s", shard.Name().c_str(),
                           pairs.size(), all.size(), pairs.empty() ? 0.0 : 1000 * reconstructed->seconds / pairs.size(),
                           computed ? "computed (shared with the other shards)" : "shared by the first shard");
    return part.Publish({{"header", BtfIndexHeader(*btf, loaded)},
                         {"entries", reconstructed->entries},
                         {"seconds", reconstructed->seconds}});
  };
  MESOCAP_RETURN_IF_ERROR(RunShardPart(folder, kStage, key, shard, fill, done_before));
  if (*done_before) summary.brief = "shard " + shard.Name() + ": done before";
  return summary;
}

StatusOr<StageSummary> MergeReconstructShards(const fs::path& session, const ReconstructStageOptions& options, int count,
                                              const std::string& key, const std::string& make_command) {
  const SessionLayout layout(session);
  const ShardsFolder folder = layout.shards(kStage, key);
  auto parts = ReadShardParts(folder, kStage, key, count, make_command);
  if (!parts.ok()) return parts.status();
  auto staging = StagingFolder::Begin(layout.btf().root);
  if (!staging.ok()) return staging.status();
  ReconstructedPairs merged;
  for (int k = 0; k < count; ++k) {
    const Json& part = (*parts)[size_t(k)];
    if (part.value("header", Json()) != parts->front().value("header", Json()))
      return Status::Error(folder.part(k + 1, count).string() + ": made from other statistics than shard 1's");
    merged.seconds += part.value("seconds", 0.0);
    for (const Json& entry : part.value("entries", Json::array())) {
      MESOCAP_RETURN_IF_ERROR(LinkPartFile(folder.part(k + 1, count), staging->path(), entry.value("file", "")));
      merged.entries.push_back(entry);
    }
  }
  const size_t expected = GridPairs(options.grid).size();
  if (merged.entries.size() != expected)
    return Status::Error(Format("the shards hold %zu slices, the %s grid %zu", merged.entries.size(),
                               options.grid.c_str(), expected));
  const Json header = parts->front().value("header", Json::object());
  auto written = WriteBtfIndex(staging->path(), header, merged, options.Provenance(session));
  if (!written.ok()) return written.status();
  MESOCAP_RETURN_IF_ERROR(staging->Publish(/*replace=*/true));
  RemoveShardParts(layout, kStage);  // every key's parts: the folder is whole now
  return ReconstructStageSummary(*written, header, options.grid);
}

}  // namespace mesocap::app

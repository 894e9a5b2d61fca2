#include "app/synth_stage.h"

#include <algorithm>

#include "app/btf_folder.h"
#include "app/shard_parts.h"
#include "app/synth_output.h"
#include "app/synth_run.h"
#include "core/atomic_file.h"
#include "core/progress.h"
#include "core/session_layout.h"
#include "core/text_format.h"

namespace mesocap::app {

namespace fs = std::filesystem;

namespace {

constexpr const char* kStage = "synth";

// The reconstructed BTF as the exemplar; `features`: with its geometry maps (for synthesis; applying
// a map needs only the slices).
// The map and what the method reports of it.
struct StageMap {
  SynthMap map;
  Json report;
  std::string note;
  TextonAnalysis textons;
};
StatusOr<StageMap> MakeMap(const fs::path& session, const Exemplar& exemplar, const SynthStageOptions& options,
                           int num_threads, bool progress) {
  SynthMethodOptions method;
  method.method = options.method;
  method.width = options.width, method.height = options.height, method.seed = options.seed;
  method.num_threads = num_threads;
  method.svd_components = ExemplarOptions().svd_components;
  StageMap made;
  ProgressBar bar(options.method, progress);
  auto map = RunSynthesisMethod(exemplar, method, &made.report, &made.note, bar.AsCallback(), &made.textons);
  if (!map.ok()) return map.status().WithContext(SessionLayout(session).btf().index().string() + ": ");
  made.map = std::move(*map);
  return made;
}

StageSummary Summary(const SynthStageOptions& options, const SynthMap& map, const Exemplar& exemplar, size_t slices,
                     const std::string& note) {
  StageSummary summary;
  summary.brief = Format("%s %dx%d from the %dx%d reconstructed BTF, %zu slices synthesized", options.method.c_str(),
                         map.width, map.height, exemplar.width, exemplar.height, slices);
  if (!note.empty()) summary.warnings.push_back(note);
  summary.report = {{"method", options.method}, {"width", map.width}, {"height", map.height}, {"slices", slices}};
  return summary;
}

// The shared folder of a sharded run: the map, the method's report and note, the exemplar's
// figures (the shards load it without features) and the method's own files (textons.exr).
struct SharedMap {
  SynthMap map;
  Json method;  // {report, note, exemplar}
};
constexpr const char* kMethodRecord = "method.json";

StatusOr<SharedMap> ReadSharedMap(const ShardsFolder& folder) {
  auto map = ReadSynthMap(SynthFolder{folder.shared()}.map());
  if (!map.ok()) return map.status();
  auto method = ReadJsonFile(folder.shared() / kMethodRecord);
  if (!method.ok()) return method.status();
  return SharedMap{std::move(*map), std::move(*method)};
}

StatusOr<SharedMap> SharedSynthesis(const fs::path& session, const SynthStageOptions& options, int num_threads,
                                    const ShardsFolder& folder, bool progress, bool* computed) {
  *computed = false;
  const auto compute = [&](const fs::path& staging) -> StatusOr<SharedMap> {
    *computed = true;
    auto exemplar = StageExemplar(session, num_threads, /*features=*/true, progress);
    if (!exemplar.ok()) return exemplar.status();
    auto made = MakeMap(session, *exemplar, options, num_threads, progress);
    if (!made.ok()) return made.status();
    MESOCAP_RETURN_IF_ERROR(WriteSynthMap(SynthFolder{staging}.map(), made->map));
    if (auto extra = TextonAnalysisWriter(made->textons)) MESOCAP_RETURN_IF_ERROR(extra(staging));
    SharedMap shared{std::move(made->map),
                     {{"report", made->report}, {"note", made->note}, {"exemplar", ExemplarReport(*exemplar)}}};
    MESOCAP_RETURN_IF_ERROR(WriteJsonFile(staging / kMethodRecord, shared.method));
    return shared;
  };
  return WithSharedFolder<SharedMap>(folder, compute, [&] { return ReadSharedMap(folder); });
}

}  // namespace

StatusOr<Exemplar> StageExemplar(const fs::path& session, int num_threads, bool features, bool progress) {
  const fs::path index = SessionLayout(session).btf().index();
  if (!fs::exists(index))
    return Status::Error(index.string() + " not found: synthesis enlarges the reconstructed BTF (run the reconstruct stage)");
  ExemplarOptions options;
  options.num_threads = num_threads;
  options.features = features;
  ProgressBar bar("features", progress && features);
  return LoadExemplar(index, options, bar.AsCallback());
}

std::vector<int> StageSlices(const Exemplar& exemplar, int max_slices) {
  std::vector<int> slices;
  for (int pass = 0; pass < 2; ++pass)
    for (size_t k = 0; k < exemplar.slices.size() && int(slices.size()) < max_slices; ++k)
      if (OnCoarseGrid(exemplar.slices[k].light) && OnCoarseGrid(exemplar.slices[k].view) ? pass == 0 : pass == 1)
        slices.push_back(int(k));
  std::sort(slices.begin(), slices.end());
  return slices;
}

StatusOr<StageSummary> RunSynthStage(const fs::path& session, const SynthStageOptions& options, int num_threads,
                                     bool progress) {
  auto exemplar = StageExemplar(session, num_threads, /*features=*/true, progress);
  if (!exemplar.ok()) return exemplar.status();
  auto made = MakeMap(session, *exemplar, options, num_threads, progress);
  if (!made.ok()) return made.status();
  SynthOutputRequest request;
  request.out = SessionLayout(session).synth().root;
  request.replace = true;
  request.num_threads = num_threads;
  request.slices = StageSlices(*exemplar, options.max_slices);
  request.report = made->report;
  request.write_extra = TextonAnalysisWriter(made->textons);
  ProgressBar write_bar("synth slices", progress);
  MESOCAP_RETURN_IF_ERROR(WriteSynthesisOutputs(made->map, *exemplar, request, write_bar.AsCallback()));
  return Summary(options, made->map, *exemplar, request.slices.size(), made->note);
}

StatusOr<StageSummary> RunSynthShard(const fs::path& session, const SynthStageOptions& options, int num_threads,
                                     const Shard& shard, const std::string& key, bool progress, bool* done_before) {
  const ShardsFolder folder = SessionLayout(session).shards(kStage, key);
  StageSummary summary;
  const auto fill = [&](PartWriter& part) -> Status {
    bool computed = false;
    auto shared = SharedSynthesis(session, options, num_threads, folder, progress, &computed);
    if (!shared.ok()) return shared.status();
    auto exemplar = StageExemplar(session, num_threads, /*features=*/false, progress);
    if (!exemplar.ok()) return exemplar.status();
    const std::vector<int> all = StageSlices(*exemplar, options.max_slices);
    const auto [first, last] = shard.Range(all.size());
    const std::vector<int> slices(all.begin() + long(first), all.begin() + long(last));
    ProgressBar bar("synth slices " + shard.Name(), progress);
    auto entries = WriteSynthesizedSlices(shared->map, *exemplar, slices, part.folder(), num_threads, bar.AsCallback());
    if (!entries.ok()) return entries.status();
    summary.brief = Format("shard %s: %zu of %zu slices, the map %s", shard.Name().c_str(), slices.size(), all.size(),
                           computed ? "made (shared with the other shards)" : "made by the first shard");
    return part.Publish({{"entries", *entries}});
  };
  MESOCAP_RETURN_IF_ERROR(RunShardPart(folder, kStage, key, shard, fill, done_before));
  if (*done_before) summary.brief = "shard " + shard.Name() + ": done before";
  return summary;
}

StatusOr<StageSummary> MergeSynthShards(const fs::path& session, const SynthStageOptions& options, int num_threads,
                                        int count, const std::string& key, const std::string& make_command) {
  const SessionLayout layout(session);
  const ShardsFolder folder = layout.shards(kStage, key);
  auto parts = ReadShardParts(folder, kStage, key, count, make_command);
  if (!parts.ok()) return parts.status();
  auto shared = ReadSharedMap(folder);
  if (!shared.ok()) return shared.status();
  const SynthMap& map = shared->map;
  const Json& method = shared->method;
  auto exemplar = StageExemplar(session, num_threads, /*features=*/false, /*progress=*/false);
  if (!exemplar.ok()) return exemplar.status();
  SynthOutputRequest request;
  request.out = layout.synth().root;
  request.replace = true;
  request.num_threads = num_threads;
  request.slices = StageSlices(*exemplar, options.max_slices);
  request.report = method.value("report", Json::object());
  request.exemplar_report = method.value("exemplar", Json::object());
  // The method's own files (textons.exr) as the first shard wrote them.
  request.write_extra = [&](const fs::path& staging) -> Status {
    for (const auto& entry : fs::directory_iterator(folder.shared())) {
      const std::string name = entry.path().filename().string();
      if (name == kMethodRecord || entry.path() == SynthFolder{folder.shared()}.map()) continue;
      std::error_code ec;
      fs::copy_file(entry.path(), staging / name, ec);
      if (ec) return Status::Error(entry.path().string() + ": cannot copy: " + ec.message());
    }
    return Status::Ok();
  };
  request.take_slices = [&](const fs::path& staging) -> StatusOr<std::vector<Json>> {
    std::vector<Json> entries;
    for (int k = 0; k < count; ++k) {
      const fs::path part = folder.part(k + 1, count);
      for (const Json& entry : (*parts)[size_t(k)].value("entries", Json::array())) {
        MESOCAP_RETURN_IF_ERROR(LinkPartFile(part, staging, entry.value("file", "")));
        entries.push_back(entry);
      }
    }
    if (entries.size() != request.slices.size())
      return Status::Error(Format("the shards hold %zu slices, the stage %zu", entries.size(), request.slices.size()));
    return entries;
  };
  MESOCAP_RETURN_IF_ERROR(WriteSynthesisOutputs(map, *exemplar, request, nullptr));
  RemoveShardParts(layout, kStage);  // every key's parts: the folder is whole now
  return Summary(options, map, *exemplar, request.slices.size(), method.value("note", ""));
}

}  // namespace mesocap::app

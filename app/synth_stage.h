// The synth stage of a session: enlarges the reconstructed BTF (SESSION/btf/) with a method into
// SESSION/synth/ (the map, the synthesized slices, previews, report.json: app/synth_output.h),
// whole or as shards (docs/workflow.md): the map is made once, by the first shard, and each shard
// applies it to a balanced share of the slices; the merge writes the folder as one run does.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "app/session_stages.h"
#include "core/shard.h"
#include "synth/exemplar.h"

namespace mesocap::app {

// The session's reconstructed BTF (SESSION/btf/) as an exemplar; an error says to reconstruct first.
StatusOr<Exemplar> StageExemplar(const std::filesystem::path& session, int num_threads, bool features, bool progress);
// Which of its slices a stage uses: those whose light and view lie on the coarse grid, then the
// rest, up to max_slices (a 6561-slice BTF at 512 x 512 would be gigabytes); in index order.
std::vector<int> StageSlices(const Exemplar& exemplar, int max_slices);

StatusOr<StageSummary> RunSynthStage(const std::filesystem::path& session, const SynthStageOptions& options,
                                     int num_threads, bool progress);
// `key`: the stage's inputs hash; `*done_before`: the part was there already.
StatusOr<StageSummary> RunSynthShard(const std::filesystem::path& session, const SynthStageOptions& options,
                                     int num_threads, const Shard& shard, const std::string& key, bool progress,
                                     bool* done_before);
StatusOr<StageSummary> MergeSynthShards(const std::filesystem::path& session, const SynthStageOptions& options,
                                        int num_threads, int count, const std::string& key, const std::string& make_command);

}  // namespace mesocap::app

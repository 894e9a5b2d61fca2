// The export stage's GGX fit as shards (docs/workflow.md): shard I of N fits a balanced band of
// whole rows of the reconstructed BTF's texels (each row's fit runs along it from its first
// texel, so a band comes out as in the whole fit) into its part; the merge puts the bands
// together into the whole fit's maps and figures, with which the export stage then runs.
#pragma once

#include <filesystem>
#include <string>

#include "app/session_stages.h"
#include "core/shard.h"
#include "export/ggx_fit.h"

namespace mesocap::app {

StatusOr<StageSummary> RunGgxShard(const std::filesystem::path& session, const Shard& shard, const std::string& key,
                                   int num_threads, bool progress, bool* done_before);
// The parts stay: remove them (RemoveShardParts) once the export made with the maps is done.
StatusOr<GgxMaterialMaps> MergeGgxShards(const std::filesystem::path& session, int count, const std::string& key,
                                         const std::string& make_command);

}  // namespace mesocap::app

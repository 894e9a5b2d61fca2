// The reconstruct stage as shards (docs/workflow.md): shard I of N reconstructs a balanced,
// contiguous share of the grid's direction pairs into its part; the statistics all shards need
// are computed once (the first shard to arrive) and read by the others; the merge checks every
// part is there and writes SESSION/btf/ exactly as the unsharded stage does (timings and
// provenance aside).
#pragma once

#include <filesystem>

#include "app/session_stages.h"
#include "core/session_layout.h"
#include "core/shard.h"

namespace mesocap::app {

// `key`: the stage's inputs hash (a part is valid only for the inputs it was made from);
// `*done_before`: the part was there already and nothing ran.
StatusOr<StageSummary> RunReconstructShard(const std::filesystem::path& session, const ReconstructStageOptions& options,
                                           const Shard& shard, const std::string& key, bool progress, bool* done_before);
// `make_command`: the command that makes a shard, for the message naming a missing one.
StatusOr<StageSummary> MergeReconstructShards(const std::filesystem::path& session, const ReconstructStageOptions& options,
                                              int count, const std::string& key, const std::string& make_command);

}  // namespace mesocap::app

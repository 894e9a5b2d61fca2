// A slice set's statistics on disk (StatisticalBtfInputs and the load's report): computed once by
// the first shard of a sharded reconstruction and read by every other shard and the merge, so
// sharding adds no statistics work (docs/workflow.md). Floats are kept exactly: a BTF made from
// the record reconstructs the same bytes as one made from the slices.
#pragma once

#include <filesystem>

#include "core/status.h"
#include "reconstruct/slice_set.h"

namespace mesocap {

struct StatisticsRecord {
  StatisticalBtfInputs inputs;
  SliceSetReport report;
};

Status WriteStatisticsRecord(const std::filesystem::path& file, const StatisticsRecord& record);
// `options`: the options the record was computed with (the caller's own; the record keeps what the
// slices decided: the colour basis and where the chromaticities come from).
StatusOr<StatisticsRecord> ReadStatisticsRecord(const std::filesystem::path& file, const StatisticalBtfOptions& options);

}  // namespace mesocap

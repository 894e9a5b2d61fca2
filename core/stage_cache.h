// What `mesocap process` remembers between runs: for every stage, the hash of what it read (its
// algorithm version and options, input files and the stages before it) and of
// what it wrote. A stage is skipped when both still match; anything else (an option, an input
// file, a deleted or edited output, a stage interrupted before it was recorded) runs it again.
// Stored in SESSION/stages.json (docs/formats.md), rewritten atomically after each stage.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/json.h"
#include "core/status.h"

namespace mesocap {

struct StageRecord {
  std::string inputs_hash;
  int version = 0;                   // the stage's algorithm version when it ran (core/stage_versions.h)
  std::string outputs_hash;
  std::vector<std::string> outputs;  // files and folders, relative to the session
  std::map<std::string, std::string> read;  // each stage it followed -> that stage's outputs_hash then
  double seconds = 0;
  std::string finished_utc;
  Json summary = Json::object();  // the stage's own brief report
  Json ToJson() const;
  static StageRecord FromJson(const Json& j);  // throws JsonFieldError
};

class StageCache {
 public:
  // Reads SESSION/stages.json if it exists. A corrupt file is an error naming it; delete it
  // to start afresh.
  static StatusOr<StageCache> Open(const std::filesystem::path& session);

  const StageRecord* Find(const std::string& stage) const;
  // Empty when `stage` was recorded with `inputs_hash` (and `version`, when given) and its outputs
  // still hash as recorded; otherwise why it must run ("never run", "a new version of the stage",
  // "its inputs ... changed", "its output slices/ is missing" ...).
  std::string WhyRun(const std::string& stage, const std::string& inputs_hash, int version = -1) const;
  // The recorded outputs hash of `stage` as it is on disk now (what a later stage's inputs
  // hash includes), or an error when the stage has no record.
  StatusOr<std::string> OutputsHash(const std::string& stage) const;

  // Whether `stage`'s outputs are as it wrote them (hashed now) and were made from `before`'s
  // outputs as recorded (process verifies those on disk before any stage reads them): the one
  // freshness rule for anything that combines two stages' outputs (export).
  bool MadeFromCurrent(const std::string& stage, const std::string& before) const;

  // Hashes the record's outputs, stores it and rewrites the file.
  Status Record(const std::string& stage, StageRecord record);

 private:
  std::filesystem::path session_;
  std::map<std::string, StageRecord> stages_;
};

// The hash of `outputs` (relative to `session`), in order, each named.
StatusOr<std::string> HashOutputs(const std::filesystem::path& session, const std::vector<std::string>& outputs);

}  // namespace mesocap

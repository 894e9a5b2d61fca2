// The parts of a sharded stage (docs/workflow.md). Each shard publishes its part whole (a staging
// folder renamed into place) with a record of its key, its shard and what the merge needs; a part
// whose record is there is done. What every shard needs but no shard should compute alone (the
// reconstruction's statistics) is computed once, by whichever shard comes first, while the others
// wait for it, and read by all.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/file_lock.h"
#include "core/json.h"
#include "core/session_layout.h"
#include "core/shard.h"
#include "core/status.h"

namespace mesocap::app {

// What a shard job writes: the part's folder to fill (a staging folder) and, once filled, its
// record; Publish makes the part appear whole.
class PartWriter {
 public:
  virtual ~PartWriter() = default;
  virtual const std::filesystem::path& folder() const = 0;
  virtual Status Publish(Json record) = 0;
};

// Runs shard `shard` of `stage` unless its part is there already (then `*done_before` is set and
// nothing runs): takes the part's own lock (the same shard running twice at once is refused),
// stages the part and calls `fill`, which writes into the folder and publishes the record.
Status RunShardPart(const ShardsFolder& folder, const std::string& stage, const std::string& key, const Shard& shard,
                    const std::function<Status(PartWriter&)>& fill, bool* done_before);

// The records of every part 1..count of `stage` under `key`, in order; a missing or foreign part
// is an error naming each missing shard and the command that makes it.
StatusOr<std::vector<Json>> ReadShardParts(const ShardsFolder& folder, const std::string& stage, const std::string& key,
                                           int count, const std::string& make_command);

// Removes every part of `stage` (all keys): its merge is done.
void RemoveShardParts(const SessionLayout& layout, const std::string& stage);

// `file` (relative to the part) taken into `folder` at the same relative path: hard-linked (the
// parts are on the session's file system; a merge that stops half way leaves every part whole),
// else copied. An empty name, or one already taken, is an error naming the part.
Status LinkPartFile(const std::filesystem::path& part, const std::filesystem::path& folder, const std::string& file);

// shared/ when this shard must make it: the lock held while it does and the staging folder to
// make it in; both empty when shared/ is there (made before, or while this shard waited).
struct SharedFolderClaim {
  std::optional<FileLock> lock;
  std::optional<StagingFolder> staging;
};
StatusOr<SharedFolderClaim> ClaimSharedFolder(const ShardsFolder& folder);

// What the shards share: `read()` from shared/ if it is there; else, under its lock, `compute(staging)`
// makes it (writing its files into the staging folder, which is then published whole) and
// returns it, so a second shard waiting on the lock then reads it.
template <class T, class Compute, class Read>
StatusOr<T> WithSharedFolder(const ShardsFolder& folder, Compute&& compute, Read&& read) {
  auto claim = ClaimSharedFolder(folder);
  if (!claim.ok()) return claim.status();
  if (!claim->staging) return read();
  StatusOr<T> made = compute(claim->staging->path());
  if (!made.ok()) return made;
  if (Status st = claim->staging->Publish(); !st.ok()) return st;
  return made;
}

}  // namespace mesocap::app

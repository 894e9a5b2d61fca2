#include "app/shard_parts.h"

#include "core/atomic_file.h"
#include "core/file_lock.h"

namespace mesocap::app {

namespace fs = std::filesystem;

namespace {

constexpr const char* kPartFormat = "mesocap-shard-part";

class StagedPart : public PartWriter {
 public:
  StagedPart(StagingFolder staging, Json identity) : staging_(std::move(staging)), identity_(std::move(identity)) {}
  const fs::path& folder() const override { return staging_.path(); }
  Status Publish(Json record) override {
    Json full = identity_;
    full.update(record);
    MESOCAP_RETURN_IF_ERROR(WriteJsonFile(staging_.path() / ShardsFolder::part_record_name(), full));
    return staging_.Publish(/*replace=*/true);
  }

 private:
  StagingFolder staging_;
  Json identity_;
};

Json PartIdentity(const std::string& stage, const std::string& key, const Shard& shard) {
  return {{"format", kPartFormat}, {"stage", stage}, {"key", key}, {"shard", shard.Name()}};
}

// The part's record if it is there and is this part's; else why not.
StatusOr<Json> ReadPart(const ShardsFolder& folder, const std::string& stage, const std::string& key, const Shard& shard) {
  const fs::path record = folder.part(shard.index, shard.count) / ShardsFolder::part_record_name();
  if (!fs::exists(record)) return Status::Error("missing");
  auto json = ReadJsonFile(record);
  if (!json.ok()) return json.status();
  const Json identity = PartIdentity(stage, key, shard);
  for (const auto& [field, value] : identity.items())
    if (json->value(field, Json()) != value) return Status::Error(record.string() + ": not this part (" + field + ")");
  return json;
}

}  // namespace

Status RunShardPart(const ShardsFolder& folder, const std::string& stage, const std::string& key, const Shard& shard,
                    const std::function<Status(PartWriter&)>& fill, bool* done_before) {
  *done_before = false;
  std::error_code ec;
  fs::create_directories(folder.root, ec);
  if (ec) return Status::Error(folder.root.string() + ": cannot create: " + ec.message());
  auto lock = FileLock::Exclusive(folder.part_lock(shard.index, shard.count), /*wait=*/false);
  if (!lock.ok()) return lock.status().WithContext("shard " + shard.Name() + ": ");
  if (ReadPart(folder, stage, key, shard).ok()) {
    *done_before = true;
    return Status::Ok();
  }
  auto staging = StagingFolder::Begin(folder.part(shard.index, shard.count));
  if (!staging.ok()) return staging.status();
  StagedPart part(std::move(*staging), PartIdentity(stage, key, shard));
  return fill(part);
}

StatusOr<std::vector<Json>> ReadShardParts(const ShardsFolder& folder, const std::string& stage, const std::string& key,
                                           int count, const std::string& make_command) {
  std::vector<Json> parts;
  std::string missing;
  for (int index = 1; index <= count; ++index) {
    const Shard shard{index, count};
    auto part = ReadPart(folder, stage, key, shard);
    if (part.ok()) {
      parts.push_back(std::move(*part));
      continue;
    }
    missing += "\n  shard " + shard.Name() + " (" + folder.part(index, count).string() + "): " + part.status().message() +
               "; make it with `" + make_command + " --shard " + shard.Name() + "`";
  }
  if (!missing.empty()) return Status::Error("cannot merge " + stage + ": not every shard is done, nothing was published:" + missing);
  return parts;
}

void RemoveShardParts(const SessionLayout& layout, const std::string& stage) {
  std::error_code ec;
  fs::remove_all(layout.shards_root() / stage, ec);  // best effort: a leftover is ignored and replaced
}

Status LinkPartFile(const fs::path& part, const fs::path& folder, const std::string& file) {
  const fs::path from = part / file, to = folder / file;
  if (file.empty() || fs::exists(to)) return Status::Error(part.string() + ": file '" + file + "' is empty or named twice");
  std::error_code ec;
  fs::create_directories(to.parent_path(), ec);
  fs::create_hard_link(from, to, ec);
  if (ec) fs::copy_file(from, to, ec);
  if (ec) return Status::Error(from.string() + ": cannot take from the shard's part: " + ec.message());
  return Status::Ok();
}

StatusOr<SharedFolderClaim> ClaimSharedFolder(const ShardsFolder& folder) {
  std::error_code ec;
  fs::create_directories(folder.root, ec);
  if (ec) return Status::Error(folder.root.string() + ": cannot create: " + ec.message());
  SharedFolderClaim claim;
  if (fs::exists(folder.shared())) return claim;
  auto lock = FileLock::Exclusive(folder.shared_lock(), /*wait=*/true);
  if (!lock.ok()) return lock.status();
  if (fs::exists(folder.shared())) return claim;  // made while this shard waited
  auto staging = StagingFolder::Begin(folder.shared());
  if (!staging.ok()) return staging.status();
  claim.lock.emplace(std::move(*lock));
  claim.staging.emplace(std::move(*staging));
  return claim;
}

}  // namespace mesocap::app

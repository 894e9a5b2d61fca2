#include "core/stage_cache.h"

#include "core/atomic_file.h"
#include "core/content_hash.h"
#include "core/session_layout.h"

namespace mesocap {

namespace fs = std::filesystem;

Json StageRecord::ToJson() const {
  return {{"inputs_hash", inputs_hash}, {"version", version},           {"outputs_hash", outputs_hash},
          {"outputs", outputs},         {"seconds", seconds},           {"finished_utc", finished_utc},
          {"summary", summary},         {"read", read}};
}

StageRecord StageRecord::FromJson(const Json& j) {
  StageRecord r;
  r.inputs_hash = JsonString(JsonField(j, "", "inputs_hash"), "inputs_hash");
  // Older files have no version: 0, which no stage has, so those stages rerun once.
  if (j.contains("version")) r.version = int(JsonNumber(j.at("version"), "version", 0, 1e6));
  r.outputs_hash = JsonString(JsonField(j, "", "outputs_hash"), "outputs_hash");
  const Json& outputs = JsonArray(JsonField(j, "", "outputs"), "outputs", 0, 64);
  for (size_t k = 0; k < outputs.size(); ++k)
    r.outputs.push_back(JsonRelativePath(outputs[k], JsonIndexPath("outputs", k)).generic_string());
  r.seconds = JsonNumber(JsonField(j, "", "seconds"), "seconds", 0, 1e9);
  r.finished_utc = JsonString(JsonField(j, "", "finished_utc"), "finished_utc");
  if (j.contains("summary") && j.at("summary").is_object()) r.summary = j.at("summary");
  if (j.contains("read")) {
    const Json& read = j.at("read");
    if (!read.is_object() || read.size() > 64) throw JsonFieldError("read is not an object of at most 64 stages");
    for (const auto& [stage, hash] : read.items()) r.read[stage] = JsonString(hash, "read." + stage);
  }
  return r;
}

StatusOr<std::string> HashOutputs(const fs::path& session, const std::vector<std::string>& outputs) {
  ContentHasher h;
  for (const std::string& o : outputs) {
    auto part = HashPath(session / o);
    if (!part.ok()) return part.status();
    h.Add(o);
    h.Add(*part);
  }
  return h.Hex();
}

StatusOr<StageCache> StageCache::Open(const fs::path& session) {
  StageCache cache;
  cache.session_ = session;
  const fs::path file = SessionLayout(session).stage_cache();
  if (!fs::exists(file)) return cache;
  auto j = ReadJsonFile(file);
  if (!j.ok()) return j.status();
  try {
    if (JsonString(JsonField(*j, "", "format"), "format") != "mesocap-stages")
      throw JsonFieldError("format is not mesocap-stages");
    const Json& stages = JsonField(*j, "", "stages");
    if (!stages.is_object()) throw JsonFieldError("stages is not an object");
    for (const auto& [name, record] : stages.items()) cache.stages_[name] = StageRecord::FromJson(record);
  } catch (const std::exception& e) {
    return Status::Error(file.string() + ": " + e.what() + " (delete it to run every stage afresh)");
  }
  return cache;
}

const StageRecord* StageCache::Find(const std::string& stage) const {
  auto it = stages_.find(stage);
  return it == stages_.end() ? nullptr : &it->second;
}

std::string StageCache::WhyRun(const std::string& stage, const std::string& inputs_hash, int version) const {
  const StageRecord* r = Find(stage);
  if (!r) return "never run";
  if (version >= 0 && r->version != version)
    return "a new version of the stage (" + std::to_string(r->version) + " -> " + std::to_string(version) + ")";
  if (r->inputs_hash != inputs_hash) return "its inputs, options or an earlier stage changed";
  for (const std::string& o : r->outputs)
    if (!fs::exists(session_ / o)) return "its output " + o + " is missing";
  auto now = HashOutputs(session_, r->outputs);
  if (!now.ok()) return now.status().message();
  if (*now != r->outputs_hash) return "its outputs were changed since it ran";
  return "";
}

bool StageCache::MadeFromCurrent(const std::string& stage, const std::string& before) const {
  const StageRecord* r = Find(stage);
  if (!r || !r->read.count(before)) return false;
  auto outputs = HashOutputs(session_, r->outputs);
  auto source = OutputsHash(before);
  return outputs.ok() && *outputs == r->outputs_hash && source.ok() && *source == r->read.at(before);
}

StatusOr<std::string> StageCache::OutputsHash(const std::string& stage) const {
  const StageRecord* r = Find(stage);
  if (!r) return Status::Error("stage " + stage + " has not run");
  return r->outputs_hash;
}

Status StageCache::Record(const std::string& stage, StageRecord record) {
  auto hash = HashOutputs(session_, record.outputs);
  if (!hash.ok()) return hash.status();
  record.outputs_hash = *hash;
  stages_[stage] = std::move(record);
  Json stages = Json::object();
  for (const auto& [name, r] : stages_) stages[name] = r.ToJson();
  return WriteJsonFile(SessionLayout(session_).stage_cache(), Json{{"format", "mesocap-stages"}, {"format_version", 1}, {"stages", stages}});
}

}  // namespace mesocap

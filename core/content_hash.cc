#include "core/content_hash.h"

#include <xxhash.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <memory>
#include <vector>

#include "core/parallel.h"

namespace mesocap {
namespace {

namespace fs = std::filesystem;

XXH3_state_t* State(void* p) { return static_cast<XXH3_state_t*>(p); }

std::string ToHex(XXH128_hash_t h) {
  char text[33];
  std::snprintf(text, sizeof text, "%016llx%016llx", static_cast<unsigned long long>(h.high64),
                static_cast<unsigned long long>(h.low64));
  return text;
}

}  // namespace

ContentHasher::ContentHasher() : state_(XXH3_createState()) { XXH3_128bits_reset(State(state_)); }
ContentHasher::~ContentHasher() { XXH3_freeState(State(state_)); }

void ContentHasher::Add(std::string_view bytes) {
  const uint64_t size = bytes.size();
  XXH3_128bits_update(State(state_), &size, sizeof size);
  XXH3_128bits_update(State(state_), bytes.data(), bytes.size());
}

Status ContentHasher::AddFile(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return Status::Error(file.string() + ": cannot read");
  std::error_code ec;
  const uint64_t size = fs::file_size(file, ec);
  if (ec) return Status::Error(file.string() + ": cannot read its size: " + ec.message());
  XXH3_128bits_update(State(state_), &size, sizeof size);
  std::vector<char> buffer(1 << 20);
  uint64_t read_total = 0;
  while (in) {
    in.read(buffer.data(), std::streamsize(buffer.size()));
    const std::streamsize got = in.gcount();
    if (got <= 0) break;
    XXH3_128bits_update(State(state_), buffer.data(), size_t(got));
    read_total += uint64_t(got);
  }
  if (in.bad() || read_total != size) return Status::Error(file.string() + ": read failed or changed while hashed");
  return Status::Ok();
}

std::string ContentHasher::Hex() const { return ToHex(XXH3_128bits_digest(State(state_))); }

std::string HashBytes(std::string_view bytes) {
  ContentHasher h;
  h.Add(bytes);
  return h.Hex();
}

StatusOr<std::string> HashFile(const fs::path& file) {
  ContentHasher h;
  MESOCAP_RETURN_IF_ERROR(h.AddFile(file));
  return h.Hex();
}

StatusOr<std::string> HashPath(const fs::path& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::exists(status)) return Status::Error(path.string() + ": missing");
  if (!fs::is_directory(status)) return HashFile(path);
  std::vector<std::string> files;
  for (fs::recursive_directory_iterator it(path, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file()) files.push_back(fs::relative(it->path(), path).generic_string());
  if (ec) return Status::Error(path.string() + ": cannot list: " + ec.message());
  std::sort(files.begin(), files.end());
  std::vector<std::string> hashes(files.size()), errors(files.size());
  ParallelFor(0, int(files.size()), [&](int k) {
    auto h = HashFile(path / files[k]);
    if (h.ok()) hashes[k] = *h;
    else errors[k] = h.status().message();
  });
  ContentHasher folder;
  folder.Add("folder");
  for (size_t k = 0; k < files.size(); ++k) {
    if (!errors[k].empty()) return Status::Error(errors[k]);
    folder.Add(files[k]);
    folder.Add(hashes[k]);
  }
  return folder.Hex();
}

}  // namespace mesocap

// Content hashes (XXH3, 128 bits, as 32 hex digits) of bytes, files and folders: what
// `mesocap process` compares to decide that a stage's inputs or outputs are unchanged. Not a
// cryptographic hash: it guards against change, not against an adversary.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "core/status.h"

namespace mesocap {

// Incremental hash of a sequence of labelled parts. Each part is framed by its length, so
// ("ab", "c") and ("a", "bc") differ.
class ContentHasher {
 public:
  ContentHasher();
  ~ContentHasher();
  ContentHasher(const ContentHasher&) = delete;
  ContentHasher& operator=(const ContentHasher&) = delete;

  void Add(std::string_view bytes);
  // The file's bytes; the error names the file.
  Status AddFile(const std::filesystem::path& file);
  // Hex of everything added so far.
  std::string Hex() const;

 private:
  void* state_;  // XXH3_state_t
};

std::string HashBytes(std::string_view bytes);
StatusOr<std::string> HashFile(const std::filesystem::path& file);
// A file's bytes, or for a folder every regular file below it (hidden ones too) by relative
// path in sorted order, each path and content hashed: renaming, adding, removing or editing any
// file changes it. Files are hashed on all cores. A missing path is an error naming it.
StatusOr<std::string> HashPath(const std::filesystem::path& path);

}  // namespace mesocap

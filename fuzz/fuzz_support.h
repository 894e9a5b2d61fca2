// Shared by the libFuzzer targets: one scratch folder per fuzzing process (the readers under test
// take paths, so each input is written to a file there first) and a helper to write bytes.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/status.h"

namespace mesocap::fuzz {

// A fresh folder under $TMPDIR (default /tmp), created on first use and removed at exit.
inline const std::filesystem::path& ScratchDir() {
  struct Dir {
    std::filesystem::path path;
    Dir() {
      const char* tmp = std::getenv("TMPDIR");
      std::string templ = std::string(tmp && *tmp ? tmp : "/tmp") + "/mesocap_fuzz_XXXXXX";
      if (!mkdtemp(templ.data())) std::abort();
      path = templ;
    }
    ~Dir() {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  };
  static const Dir dir;
  return dir.path;
}

// Replaces `path` with exactly `size` bytes of `data`; aborts on I/O failure (the harness's
// fault, not the reader's).
inline void WriteBytes(const std::filesystem::path& path, const uint8_t* data, size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  out.close();
  if (!out) std::abort();
}

inline void WriteText(const std::filesystem::path& path, const std::string& text) {
  WriteBytes(path, reinterpret_cast<const uint8_t*>(text.data()), text.size());
}

// Runs one reader call. An exception escaping a reader is a bug (bad data must come back as a
// Status) and crashes the fuzzer, with the throw site on the stack. While such a bug is being
// fixed, MESOCAP_FUZZ_TOLERATE="text;text" lets exceptions whose what() contains one of the texts
// pass, so fuzzing goes on past it; any other exception still crashes.
template <typename Fn>
void Run(Fn&& read) {
  static const std::vector<std::string> tolerated = [] {
    std::vector<std::string> out;
    const char* env = std::getenv("MESOCAP_FUZZ_TOLERATE");
    std::string list = env ? env : "";
    for (size_t start = 0; start < list.size();) {
      size_t end = list.find(';', start);
      if (end == std::string::npos) end = list.size();
      if (end > start) out.push_back(list.substr(start, end - start));
      start = end + 1;
    }
    return out;
  }();
  if (tolerated.empty()) {
    read();
    return;
  }
  try {
    read();
  } catch (const std::exception& e) {
    for (const std::string& t : tolerated)
      if (std::strstr(e.what(), t.c_str())) return;
    throw;
  }
}

// With MESOCAP_FUZZ_VERBOSE set (triage, seed checks), prints what the reader said of the input.
inline void Explain(const char* what, const Status& status) {
  static const bool verbose = std::getenv("MESOCAP_FUZZ_VERBOSE") != nullptr;
  if (verbose) std::fprintf(stderr, "%s: %s\n", what, status.message().c_str());
}

}  // namespace mesocap::fuzz

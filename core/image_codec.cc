#include "core/image_codec.h"

#include <dlfcn.h>
#include <unistd.h>

#include <climits>

namespace mesocap {
namespace {

namespace fs = std::filesystem;

// The folder of the running executable ("" if unknown).
fs::path ExecutableFolder() {
  char self[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  if (n <= 0) return {};
  return fs::path(std::string(self, size_t(n))).parent_path();
}

// Where the module may be: beside the executable (installed, or mesocap in the build tree next
// to its copy), then where the build made it (tests, benchmarks and fuzzers in other folders).
std::vector<fs::path> ModuleCandidates() {
  std::vector<fs::path> candidates;
  if (const fs::path folder = ExecutableFolder(); !folder.empty()) candidates.push_back(folder / kImageCodecModuleName);
#ifdef MESOCAP_IMAGE_CODEC_BUILD_PATH
  candidates.push_back(MESOCAP_IMAGE_CODEC_BUILD_PATH);
#endif
  return candidates;
}

StatusOr<ImageCodec*> Load() {
  std::string tried;
  for (const fs::path& candidate : ModuleCandidates()) {
    std::error_code ec;
    if (!fs::is_regular_file(candidate, ec)) {
      tried += " " + candidate.string() + " (missing);";
      continue;
    }
    void* module = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!module) {
      tried += " " + candidate.string() + " (" + dlerror() + ");";
      continue;
    }
    auto factory = reinterpret_cast<ImageCodecFactory>(dlsym(module, kImageCodecFactorySymbol));
    if (!factory) {
      tried += " " + candidate.string() + " (no " + kImageCodecFactorySymbol + ");";
      continue;
    }
    return factory();  // the module stays loaded for the life of the process
  }
  return Status::Error(std::string("cannot load the image codec module ") + kImageCodecModuleName + ":" + tried +
                       " reinstall mesocap");
}

}  // namespace

StatusOr<ImageCodec*> LoadImageCodec() {
  static const StatusOr<ImageCodec*> codec = Load();  // thread-safe once
  return codec;
}

}  // namespace mesocap

#include "core/image_codec.h"

#include "core/module_loader.h"

namespace mesocap {

// Where the build made the module, tried after the executable's folder: tests, benchmarks and
// fuzzers run from other folders.
#ifdef MESOCAP_IMAGE_CODEC_BUILD_PATH
static constexpr const char* kBuildPath = MESOCAP_IMAGE_CODEC_BUILD_PATH;
#else
static constexpr const char* kBuildPath = "";
#endif

StatusOr<ImageCodec*> LoadImageCodec() {
  // Thread-safe once; the module stays loaded for the life of the process.
  static const StatusOr<ImageCodec*> codec =
      LoadModuleObject<ImageCodec>(kImageCodecModuleName, kBuildPath, kImageCodecFactorySymbol);
  return codec;
}

}  // namespace mesocap

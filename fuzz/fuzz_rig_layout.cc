// rig_layout.json through core/json.h ReadJsonFile and core/rig_layout.h RigLayout::FromJson,
// as `mesocap calibrate` reads it (app/calibrate_cmd.cc).
#include "core/json.h"
#include "core/rig_layout.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = mesocap::fuzz::ScratchDir() / "rig_layout.json";
  mesocap::fuzz::WriteBytes(path, data, size);
  mesocap::fuzz::Run([&] {
    auto json = mesocap::ReadJsonFile(path);
    mesocap::fuzz::Explain("ReadJsonFile", json.status());
    if (!json.ok()) return;
    auto layout = mesocap::RigLayout::FromJson(*json);
    mesocap::fuzz::Explain("RigLayout::FromJson", layout.status());
    if (layout.ok()) (void)layout->ToJson().dump();
  });
  return 0;
}

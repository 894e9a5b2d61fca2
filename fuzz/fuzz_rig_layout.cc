// rig_layout.json through core/json.h ReadJsonFile and core/rig_layout.h RigLayout::FromJson,
// as `mesocap calibrate` reads it (app/calibrate_cmd.cc).
#include "core/rig_layout.h"
#include "fuzz/fuzz_json.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  mesocap::fuzz::FuzzJsonFile("rig_layout.json", data, size, [](const mesocap::Json& json) {
    auto layout = mesocap::RigLayout::FromJson(json);
    mesocap::fuzz::Explain("RigLayout::FromJson", layout.status());
    if (layout.ok()) (void)layout->ToJson().dump();
  });
  return 0;
}

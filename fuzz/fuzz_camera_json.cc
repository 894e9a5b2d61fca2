// camera.json (calibrate-camera's output, `mesocap calibrate --camera`) through core/json.h
// ReadJsonFile and core/camera_model.h CameraModel::FromJson, exactly as app/calibrate_cmd.cc
// reads it: FromJson reports bad data by throwing, and that caller turns it into a Status
// ("not a camera file").
#include "core/camera_model.h"
#include "fuzz/fuzz_json.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  mesocap::fuzz::FuzzJsonFile("camera.json", data, size, [](const mesocap::Json& json) {
    mesocap::fuzz::ExplainThrowing("CameraModel::FromJson", [&] {
      const mesocap::CameraModel camera = mesocap::CameraModel::FromJson(json.contains("camera") ? json.at("camera") : json);
      (void)camera.ToJson().dump();
    });
  });
  return 0;
}

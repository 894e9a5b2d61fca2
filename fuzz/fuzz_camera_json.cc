// camera.json (calibrate-camera's output, `mesocap calibrate --camera`) through core/json.h
// ReadJsonFile and core/camera_model.h CameraModel::FromJson, exactly as app/calibrate_cmd.cc
// reads it: FromJson reports bad data by throwing, and that caller turns it into a Status.
#include <exception>

#include "core/camera_model.h"
#include "core/json.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = mesocap::fuzz::ScratchDir() / "camera.json";
  mesocap::fuzz::WriteBytes(path, data, size);
  mesocap::fuzz::Run([&] {
    auto json = mesocap::ReadJsonFile(path);
    mesocap::fuzz::Explain("ReadJsonFile", json.status());
    if (!json.ok()) return;
    try {
      const mesocap::CameraModel camera =
          mesocap::CameraModel::FromJson(json->contains("camera") ? json->at("camera") : *json);
      (void)camera.ToJson().dump();
      mesocap::fuzz::Explain("CameraModel::FromJson", mesocap::Status::Ok());
    } catch (const std::exception& e) {  // app/calibrate_cmd.cc: "not a camera file"
      mesocap::fuzz::Explain("CameraModel::FromJson", mesocap::Status::Error(e.what()));
    }
  });
  return 0;
}

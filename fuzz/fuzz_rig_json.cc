// calibration/rig.json through core/json.h ReadJsonFile and calib/calibrate.h
// CalibrationResult::FromRigJson, as app/session_stages.cc LoadSessionCalibration reads it:
// FromRigJson reports bad data by throwing, and that caller turns it into a Status.
#include <exception>

#include "calib/calibrate.h"
#include "core/json.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = mesocap::fuzz::ScratchDir() / "rig.json";
  mesocap::fuzz::WriteBytes(path, data, size);
  mesocap::fuzz::Run([&] {
    auto json = mesocap::ReadJsonFile(path);
    mesocap::fuzz::Explain("ReadJsonFile", json.status());
    if (!json.ok()) return;
    try {
      const mesocap::CalibrationResult rig = mesocap::CalibrationResult::FromRigJson(*json);
      (void)rig.RigJson().dump();
      (void)rig.usable_shots();
      mesocap::fuzz::Explain("CalibrationResult::FromRigJson", mesocap::Status::Ok());
    } catch (const std::exception& e) {  // LoadSessionCalibration: "rig.json: <field>"
      mesocap::fuzz::Explain("CalibrationResult::FromRigJson", mesocap::Status::Error(e.what()));
    }
  });
  return 0;
}

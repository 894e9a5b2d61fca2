// calibration/rig.json through core/json.h ReadJsonFile and calib/calibrate.h
// CalibrationResult::FromRigJson, as app/session_stages.cc LoadSessionCalibration reads it:
// FromRigJson reports bad data by throwing, and that caller turns it into a Status ("rig.json:
// <field>").
#include "calib/calibrate.h"
#include "fuzz/fuzz_json.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  mesocap::fuzz::FuzzJsonFile("rig.json", data, size, [](const mesocap::Json& json) {
    mesocap::fuzz::ExplainThrowing("CalibrationResult::FromRigJson", [&] {
      const mesocap::CalibrationResult rig = mesocap::CalibrationResult::FromRigJson(json);
      (void)rig.RigJson().dump();
      (void)rig.usable_shots();
    });
  });
  return 0;
}

#include "app/guided_capture.h"

#include <map>
#include <string>

#include "capture/virtual_camera.h"
#include "core/json.h"
#include "core/rig_layout.h"
#include "core/session_layout.h"

namespace mesocap::app {
namespace fs = std::filesystem;

StatusOr<std::unique_ptr<CaptureGuide>> StartGuide(Camera& camera, CaptureGuideOptions options) {
  const SessionLayout layout(options.session);
  if (auto* virtual_camera = dynamic_cast<VirtualCamera*>(&camera);
      virtual_camera && options.layout_file.empty() && !fs::exists(layout.rig_layout()))
    MESOCAP_RETURN_IF_ERROR(WriteJsonFile(layout.rig_layout(), LayoutOf(virtual_camera->scene()).ToJson()));
  return CaptureGuide::Start(options);
}

CameraStatus HoldFlashAt(Camera& camera, const std::optional<Eigen::Vector3d>& suggestion) {
  return camera.SetConfig(kFlashPositionSetting, suggestion ? FlashPositionValue(*suggestion) : kFlashHandHeld);
}

Status WriteVirtualTruth(Camera& camera, const CaptureReport& report, const fs::path& session) {
  const auto* virtual_camera = dynamic_cast<const VirtualCamera*>(&camera);
  if (!virtual_camera) return Status::Ok();
  std::map<std::string, std::string> session_files;
  for (const CapturedShot& shot : report.shots) session_files[fs::path(shot.on_card).filename().string()] = shot.file;
  Json truth = virtual_camera->TruthOfShotsTaken(session_files);
  const fs::path truth_file = SessionLayout(session).truth();
  if (fs::exists(truth_file)) {
    auto earlier = ReadJsonFile(truth_file);
    if (!earlier.ok()) return Status::Error(earlier.status().message() + " (not rewritten with this run's shots)");
    if (!earlier->is_object())
      return Status::Error(truth_file.string() + ": not a JSON object (not rewritten with this run's shots)");
    for (const char* list : {"shots", "calib_shots"}) {
      Json merged = earlier->value(list, Json::array());
      for (const Json& shot : truth[list]) merged.push_back(shot);
      truth[list] = merged;
    }
  }
  return WriteJsonFile(truth_file, truth);
}

}  // namespace mesocap::app

// What `mesocap capture --guide` and `mesocap console` share around a tethered capture: starting
// the guidance on a session, the virtual photographer following it, and the virtual rig's truth
// of the shots taken.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>

#include "app/capture_guide.h"
#include "capture/camera.h"
#include "capture/tethered_capture.h"

namespace mesocap::app {

// Starts the guidance on `options.session`. The virtual rig knows its layout, as a lab keeps its
// pyramid's on file: with the virtual camera and no layout, SESSION/rig_layout.json is written
// from it first.
StatusOr<std::unique_ptr<CaptureGuide>> StartGuide(Camera& camera, CaptureGuideOptions options);

// The virtual photographer holds the flash at `suggestion` (camera frame), or by hand without one.
CameraStatus HoldFlashAt(Camera& camera, const std::optional<Eigen::Vector3d>& suggestion);

// A virtual capture knows its ground truth: SESSION/truth.json as `mesocap simulate` writes it,
// with every shot of `report` as taken (the flash where the guidance or the hand put it, at its
// power) under its name in the session. A resumed session's earlier shots are kept; an earlier
// truth.json that cannot be read is left as it is, and said so. Nothing for another camera.
Status WriteVirtualTruth(Camera& camera, const CaptureReport& report, const std::filesystem::path& session);

}  // namespace mesocap::app

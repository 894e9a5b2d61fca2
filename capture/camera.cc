#include "capture/camera.h"

#include <algorithm>
#include <cctype>

#include "capture/fake_camera.h"
#include "capture/virtual_camera.h"
#include "capture/gphoto2_camera.h"

namespace mesocap {
namespace fs = std::filesystem;

std::string CameraErrorToString(CameraError error) {
  switch (error) {
    case CameraError::kOk: return "ok";
    case CameraError::kBusy: return "busy";
    case CameraError::kIo: return "io";
    case CameraError::kGone: return "gone";
    case CameraError::kCardFull: return "card_full";
    case CameraError::kDiskFull: return "disk_full";
    case CameraError::kBadSetting: return "bad_setting";
    case CameraError::kNotSupported: return "not_supported";
    case CameraError::kTimeout: return "timeout";
    case CameraError::kOther: return "other";
  }
  return "other";
}

StatusOr<std::unique_ptr<Camera>> CreateCamera(const std::string& model, const std::string& port) {
  if (model == "fake") {
    if (port.empty()) return Status::Error("--camera fake needs --port FOLDER (a folder of photos to serve)");
    std::error_code ec;
    FakeCameraOptions options;
    options.port = "fake:" + port;
    for (fs::directory_iterator it(port, ec), end; !ec && it != end; it.increment(ec))
      if (it->is_regular_file()) options.photos.push_back(it->path());
    if (ec) return Status::Error(port + ": cannot list folder: " + ec.message());
    if (options.photos.empty()) return Status::Error(port + ": no photos to serve");
    std::sort(options.photos.begin(), options.photos.end());
    return std::unique_ptr<Camera>(std::make_unique<FakeCamera>(std::move(options)));
  }
  if (model == "virtual") {
    auto camera = VirtualCamera::Open(port);
    if (!camera.ok()) return camera.status();
    return std::unique_ptr<Camera>(std::move(*camera));
  }
  auto camera = Gphoto2Camera::Open(model, port);
  if (!camera.ok()) return camera.status();
  return std::unique_ptr<Camera>(std::move(*camera));
}

StatusOr<std::vector<CameraInfo>> ListCameras() { return Gphoto2Camera::Detect(); }

}  // namespace mesocap

// The libgphoto2 back-end of capture/camera.h: any body libgphoto2 drives over USB/PTP, and in
// tests libgphoto2's virtual USB camera (scripts/build-vusb.sh, run with IOLIBS=<its folder>).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "capture/camera.h"

struct _Camera;     // libgphoto2's Camera
struct _GPContext;  // libgphoto2's GPContext

namespace mesocap {

class Gphoto2Camera : public Camera {
 public:
  // See CreateCamera in capture/camera.h for how model and port pick the camera.
  static StatusOr<std::unique_ptr<Gphoto2Camera>> Open(const std::string& model, const std::string& port);
  // gp_camera_autodetect.
  static StatusOr<std::vector<CameraInfo>> Detect();

  ~Gphoto2Camera() override;
  Gphoto2Camera(const Gphoto2Camera&) = delete;
  Gphoto2Camera& operator=(const Gphoto2Camera&) = delete;

  CameraInfo info() const override { return info_; }
  CameraStatus ListConfig(std::vector<ConfigEntry>* entries) override;
  CameraStatus GetConfig(const std::string& name, ConfigEntry* entry) override;
  CameraStatus SetConfig(const std::string& name, const std::string& value) override;
  CameraStatus Capture(CameraFilePath* on_card) override;
  CameraStatus TriggerCapture() override;
  CameraStatus WaitForFileAdded(double timeout_s, CameraFilePath* added, bool* got) override;
  CameraStatus Download(const CameraFilePath& on_card, const std::filesystem::path& dest, int64_t* bytes,
                        int64_t* expected_bytes) override;
  CameraStatus DeleteFile(const CameraFilePath& on_card) override;
  void Close() override;

 private:
  struct Context;  // the GPContext and the last error message libgphoto2 reported through it
  Gphoto2Camera(_Camera* camera, std::unique_ptr<Context> context, CameraInfo info);
  // Maps a libgphoto2 result to a CameraStatus naming `what` and the context's last message.
  CameraStatus Check(int result, const std::string& what) const;

  _Camera* camera_ = nullptr;
  std::unique_ptr<Context> context_;
  CameraInfo info_;
};

}  // namespace mesocap

// The virtual rig as a third back-end of capture/camera.h: `mesocap capture --camera virtual`
// renders each picture the moment the shutter fires, so a capture run through it yields the
// same session (bytes included) as `mesocap simulate` with the same options.
// Port: "virtual" or "virtual:seed=S,material=M,width=W,height=H,shots=N,calib-shots=C,format=F,
// follow-error=E". The setting "flashposition" stands for the photographer holding the flash:
// "hand-held" (the rig's next position, as `simulate` renders them) or "x,y,z", metres in the
// camera frame, where the next flash shots are taken (guided capture, `mesocap capture
// --follow-guide`, the console), missed by a person's error: a random offset of E metres standard
// deviation along each axis (default 0: exactly there).
#pragma once

#include <deque>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "capture/camera.h"
#include "capture/rig_material.h"
#include "capture/rig_render.h"
#include "capture/rig_scene.h"
#include "core/json.h"

namespace mesocap {

// The setting's name and its hand-held value; FlashPositionValue(p) is the value for position p.
inline constexpr const char* kFlashPositionSetting = "flashposition";
inline constexpr const char* kFlashHandHeld = "hand-held";
std::string FlashPositionValue(const Eigen::Vector3d& position_cam);

class VirtualCamera : public Camera {
 public:
  // Parses the port's options; renders nothing yet.
  static StatusOr<std::unique_ptr<VirtualCamera>> Open(const std::string& port);
  ~VirtualCamera() override;

  CameraInfo info() const override { return {"mesocap virtual rig", port_}; }
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

  const RigScene& scene() const { return *scene_; }
  // Every flash shot taken so far, in order, with the flash where it really was (the truth).
  const std::vector<RigShot>& flash_shots_taken() const { return taken_; }
  // The truth of the shots taken so far, as `mesocap simulate` writes truth.json: the rig, and
  // each shot under the name `session_files` gives its name on the card (shots it does not name
  // are left out).
  Json TruthOfShotsTaken(const std::map<std::string, std::string>& session_files) const;

 private:
  VirtualCamera() = default;
  CameraStatus Render(CameraFilePath* on_card);

  std::string port_, format_ = "jpg";
  std::unique_ptr<RigScene> scene_;
  std::unique_ptr<Material> material_;
  std::unique_ptr<RigRenderer> renderer_;  // prepared at the first capture
  std::vector<ConfigEntry> config_;
  std::filesystem::path card_;  // a temp folder standing in for the memory card
  RigShot NextFlash(CameraStatus* status);

  uint64_t seed_ = 1;
  double follow_error_m_ = 0;  // a person's miss of an asked flash position, per axis (m)
  int next_flash_ = 0, next_calib_ = 0;  // the rig's hand-held flash positions, checkerboard poses
  std::vector<RigShot> taken_;
  std::vector<RigCalibShot> calib_taken_;
  std::deque<CameraFilePath> events_;
  bool closed_ = false;
};

}  // namespace mesocap

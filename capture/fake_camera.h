// A fake back-end of capture/camera.h for tests: serves a list of photo files in turn and
// injects the faults a tethered session meets (busy camera, unplugged camera, damaged download,
// full disk). Captures are numbered from 1 in the order Capture()/TriggerCapture() is called.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "capture/camera.h"

namespace mesocap {

struct FakeCameraOptions {
  std::vector<std::filesystem::path> photos;  // served in turn, cycling; must not be empty
  std::string model = "mesocap fake camera";
  std::string port = "fake:";
  double capture_delay_s = 0;  // each Capture() takes this long (for kill tests)

  // Faults, by capture number (1-based).
  std::map<int, int> busy_at;          // capture k fails kBusy this many times before it succeeds
  int disconnect_after = -1;           // after this many successful captures the camera is gone
  std::map<int, int> corrupt_download_at;  // capture k's download is truncated this many times
  bool corrupt_keeps_size = false;     // corrupt downloads report the truncated size (so only the
                                       // file's content shows the damage)
  std::set<int> disk_full_at;          // capture k's download fails kDiskFull
  int card_capacity = -1;              // captures the card holds (-1: unlimited), then kCardFull
};

class FakeCamera : public Camera {
 public:
  explicit FakeCamera(FakeCameraOptions options);

  CameraInfo info() const override { return {options_.model, options_.port}; }
  CameraStatus ListConfig(std::vector<ConfigEntry>* entries) override;
  CameraStatus GetConfig(const std::string& name, ConfigEntry* entry) override;
  CameraStatus SetConfig(const std::string& name, const std::string& value) override;
  CameraStatus Capture(CameraFilePath* on_card) override;
  CameraStatus TriggerCapture() override;
  CameraStatus WaitForFileAdded(double timeout_s, CameraFilePath* added, bool* got) override;
  CameraStatus Download(const CameraFilePath& on_card, const std::filesystem::path& dest, int64_t* bytes,
                        int64_t* expected_bytes) override;
  CameraStatus DeleteFile(const CameraFilePath& on_card) override;
  void Close() override { closed_ = true; }

  // What happened, for tests.
  int captures() const { return captures_; }
  int downloads() const { return downloads_; }
  int capture_attempts() const { return capture_attempts_; }
  int files_on_card() const { return int(card_.size()); }
  // The photo served for a file on the fake card ("" when unknown).
  std::filesystem::path SourceOf(const CameraFilePath& on_card) const;

 private:
  CameraStatus Gone() const;
  CameraStatus TakePicture(CameraFilePath* on_card);

  FakeCameraOptions options_;
  std::vector<ConfigEntry> config_;
  std::map<std::string, std::filesystem::path> card_;  // name on card -> served photo
  std::map<std::string, int> capture_number_;          // name on card -> capture number
  std::vector<CameraFilePath> pending_events_;
  std::map<int, int> busy_left_, corrupt_left_;
  int captures_ = 0, downloads_ = 0, capture_attempts_ = 0;
  bool closed_ = false;
};

}  // namespace mesocap

// A tethered camera, behind one interface: libgphoto2 for real bodies (and libgphoto2's virtual
// USB camera in tests), and a fake back-end that injects faults (busy, disconnect, corrupt
// download, disk full). `mesocap capture` drives a Camera through capture/tethered_capture.h.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "core/status.h"

namespace mesocap {

// Why a camera call failed, so the capture loop can decide: retry (busy, I/O) or stop.
enum class CameraError {
  kOk,
  kBusy,          // the camera is busy (focusing, writing the card): retry after a pause
  kIo,            // a transfer failed or came back damaged: retry
  kGone,          // the camera is unplugged or switched off: stop, keep what was captured
  kCardFull,      // the camera's card or buffer is full: stop
  kDiskFull,      // no space left on the computer's disk: stop
  kBadSetting,    // unknown configuration key or invalid value (the message lists the choices)
  kNotSupported,  // the body cannot do this (e.g. no remote trigger)
  kTimeout,       // nothing happened within the time asked for
  kOther,
};
std::string CameraErrorToString(CameraError error);  // "ok", "busy", "io", "gone", ...

// A Status plus the kind of failure.
struct CameraStatus {
  CameraError error = CameraError::kOk;
  std::string message;  // names the camera, the file on the card or the local path involved

  bool ok() const { return error == CameraError::kOk; }
  bool retryable() const { return error == CameraError::kBusy || error == CameraError::kIo; }
  Status ToStatus() const { return ok() ? Status::Ok() : Status::Error(message); }
  static CameraStatus Ok() { return {}; }
  static CameraStatus Error(CameraError error, std::string message) { return {error, std::move(message)}; }
};

// A detected camera: what `mesocap cameras` lists and what --camera / --port pick from.
struct CameraInfo {
  std::string model;  // "Nikon DSC D750"
  std::string port;   // "usb:001,004"
};

// One configuration entry (a leaf of libgphoto2's widget tree).
struct ConfigEntry {
  std::string name;    // short key used with --set: "iso", "shutterspeed", "f-number" ...
  std::string label;   // human label: "ISO Speed"
  std::string type;    // "radio", "menu", "text", "range", "toggle", "date"
  std::string value;   // current value as text
  std::vector<std::string> choices;  // radio/menu: every valid value; range: "min..max step s"
  bool read_only = false;
};

// A file on the camera's card (or in its RAM buffer).
struct CameraFilePath {
  std::string folder;  // "/store_00010001/DCIM/100D7500"
  std::string name;    // "DSC_0042.JPG"
  std::string ToString() const { return folder == "/" ? "/" + name : folder + "/" + name; }
};

class Camera {
 public:
  virtual ~Camera() = default;

  virtual CameraInfo info() const = 0;

  // Every configuration entry, in the camera's order.
  virtual CameraStatus ListConfig(std::vector<ConfigEntry>* entries) = 0;
  // One entry by name; an unknown name is kBadSetting and the message lists the known names.
  virtual CameraStatus GetConfig(const std::string& name, ConfigEntry* entry) = 0;
  // Sets one entry by name. An unknown name, a read-only entry or a value that is not among the
  // choices (radio/menu) or out of range is kBadSetting, with the valid keys or values listed.
  virtual CameraStatus SetConfig(const std::string& name, const std::string& value) = 0;

  // Takes one picture and waits until it is stored; *on_card is where it is.
  virtual CameraStatus Capture(CameraFilePath* on_card) = 0;
  // Fires the shutter without waiting for the file; it arrives as a FILE_ADDED event.
  virtual CameraStatus TriggerCapture() = 0;
  // Waits up to `timeout_s` for a FILE_ADDED event (the photographer fired the camera, or an
  // earlier TriggerCapture). *got is false when the time ran out with no new file.
  virtual CameraStatus WaitForFileAdded(double timeout_s, CameraFilePath* added, bool* got) = 0;
  // Downloads a file from the card to `dest` (created or truncated; the caller makes it
  // durable and renames it). *bytes is the size written; *expected_bytes the size the camera
  // reports for the file, or -1 when it does not say.
  virtual CameraStatus Download(const CameraFilePath& on_card, const std::filesystem::path& dest,
                                int64_t* bytes, int64_t* expected_bytes) = 0;

  // Deletes a file from the card (or frees it from the camera's RAM buffer).
  virtual CameraStatus DeleteFile(const CameraFilePath& on_card) = 0;

  // Releases the camera; calls after Close() fail with kGone. The destructor closes too.
  virtual void Close() = 0;
};

// Opens a camera:
//   model "fake", port = a folder of photos: a FakeCamera serving them in turn (no faults);
//   anything else: libgphoto2. With neither model nor port, the one detected camera (an error
//   when there are none or several, listing them); with a model and/or a port, the detected
//   camera that matches, or (model and port both given) that driver on that port.
StatusOr<std::unique_ptr<Camera>> CreateCamera(const std::string& model = "", const std::string& port = "");

// Cameras libgphoto2 detects now (`mesocap cameras`). Honours IOLIBS/CAMLIBS like libgphoto2.
StatusOr<std::vector<CameraInfo>> ListCameras();

}  // namespace mesocap

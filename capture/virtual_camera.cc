#include "capture/virtual_camera.h"

#include <unistd.h>

#include <cmath>
#include <optional>
#include <random>
#include <sstream>

#include "capture/simulate.h"
#include "core/image_io.h"

namespace mesocap {
namespace fs = std::filesystem;

namespace {

ConfigEntry Radio(const std::string& name, const std::string& label, const std::string& value,
                  std::vector<std::string> choices, bool read_only = false) {
  return {name, label, "radio", value, std::move(choices), read_only};
}

// "x,y,z" in metres -> a position; false when it is not three finite numbers.
bool ParsePosition(const std::string& text, Eigen::Vector3d* position) {
  std::stringstream ss(text);
  std::string item;
  int n = 0;
  while (std::getline(ss, item, ',')) {
    if (n == 3) return false;
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0' || !std::isfinite(v)) return false;
    (*position)[n++] = v;
  }
  return n == 3;
}

}  // namespace

std::string FlashPositionValue(const Eigen::Vector3d& p) {
  return std::to_string(p.x()) + "," + std::to_string(p.y()) + "," + std::to_string(p.z());
}

StatusOr<std::unique_ptr<VirtualCamera>> VirtualCamera::Open(const std::string& port) {
  std::unique_ptr<VirtualCamera> cam(new VirtualCamera());
  cam->port_ = port.empty() ? "virtual" : port;
  RigOptions o;
  const std::string prefix = "virtual:";
  if (port.rfind(prefix, 0) == 0) {
    std::stringstream ss(port.substr(prefix.size()));
    std::string item;
    while (std::getline(ss, item, ',')) {
      const auto eq = item.find('=');
      if (eq == std::string::npos) return Status::Error("virtual camera port: expected key=value, got '" + item + "'");
      const std::string key = item.substr(0, eq), value = item.substr(eq + 1);
      try {
        if (key == "seed") o.seed = std::stoull(value);
        else if (key == "material") o.material = value;
        else if (key == "width") o.width = std::stoi(value);
        else if (key == "height") o.height = std::stoi(value);
        else if (key == "shots") o.shots = std::stoi(value);
        else if (key == "calib-shots") o.calib_shots = std::stoi(value);
        else if (key == "format") cam->format_ = value;
        else if (key == "follow-error") cam->follow_error_m_ = std::stod(value);
        else
          return Status::Error("virtual camera port: unknown key '" + key +
                               "' (seed, material, width, height, shots, calib-shots, format, follow-error)");
      } catch (const std::exception&) {
        return Status::Error("virtual camera port: bad value for " + key + ": '" + value + "'");
      }
    }
  } else if (!port.empty() && port != "virtual") {
    return Status::Error("virtual camera port must be 'virtual' or 'virtual:key=value,...', not '" + port + "'");
  }
  if (ExtensionForFormat(cam->format_).empty()) return Status::Error("virtual camera: format must be jpg, png or exr");
  if (!(cam->follow_error_m_ >= 0 && cam->follow_error_m_ <= 1))
    return Status::Error("virtual camera: follow-error must be 0 to 1 metre");
  cam->seed_ = o.seed;
  auto scene = MakeRigScene(o);
  if (!scene.ok()) return scene.status();
  auto material = Material::Create(o.material);
  if (!material.ok()) return material.status();
  cam->scene_ = std::make_unique<RigScene>(std::move(*scene));
  cam->material_ = std::make_unique<Material>(std::move(*material));
  cam->config_ = {Radio("subject", "What the next shot shows", "flash", {"flash", "checkerboard"}),
                  Radio("iso", "ISO Speed", "100", {"100"}, true),
                  Radio("shutterspeed", "Shutter Speed", "1/125", {"1/125"}, true),
                  Radio("f-number", "F-Number", "f/8", {"f/8"}, true),
                  Radio("flashmode", "Flash Mode", "on", {"on"}, true),
                  Radio("imageformat", "Image Format", cam->format_, {cam->format_}, true),
                  {kFlashPositionSetting, "Where the photographer holds the flash: hand-held, or x,y,z (m, camera frame)",
                   "text", kFlashHandHeld, {}, false}};
  cam->card_ = fs::temp_directory_path() / ("mesocap-virtual-card-" + std::to_string(::getpid()) + "-" +
                                            std::to_string(reinterpret_cast<uintptr_t>(cam.get())));
  std::error_code ec;
  fs::create_directories(cam->card_ / "DCIM" / "100VIRT", ec);
  if (ec) return Status::Error(cam->card_.string() + ": cannot create the virtual card: " + ec.message());
  return cam;
}

VirtualCamera::~VirtualCamera() { Close(); }

void VirtualCamera::Close() {
  if (closed_) return;
  closed_ = true;
  std::error_code ec;
  fs::remove_all(card_, ec);
}

CameraStatus VirtualCamera::ListConfig(std::vector<ConfigEntry>* entries) {
  if (closed_) return CameraStatus::Error(CameraError::kGone, "virtual camera: closed");
  *entries = config_;
  return CameraStatus::Ok();
}

CameraStatus VirtualCamera::GetConfig(const std::string& name, ConfigEntry* entry) {
  std::string names;
  for (const auto& e : config_) {
    if (e.name == name) {
      *entry = e;
      return CameraStatus::Ok();
    }
    names += (names.empty() ? "" : ", ") + e.name;
  }
  return CameraStatus::Error(CameraError::kBadSetting, "virtual camera: no setting '" + name + "' (settings: " + names + ")");
}

CameraStatus VirtualCamera::SetConfig(const std::string& name, const std::string& value) {
  ConfigEntry entry;
  if (CameraStatus st = GetConfig(name, &entry); !st.ok()) return st;
  Eigen::Vector3d position;
  if (entry.type == "text" && value != kFlashHandHeld && !ParsePosition(value, &position))
    return CameraStatus::Error(CameraError::kBadSetting, "virtual camera: " + name + " must be '" + kFlashHandHeld +
                                                             "' or x,y,z in metres (camera frame), not '" + value + "'");
  if (entry.type != "text" && std::find(entry.choices.begin(), entry.choices.end(), value) == entry.choices.end()) {
    std::string choices;
    for (const auto& c : entry.choices) choices += (choices.empty() ? "" : ", ") + c;
    return CameraStatus::Error(CameraError::kBadSetting,
                               "virtual camera: '" + value + "' is not a value of " + name + " (choices: " + choices + ")");
  }
  for (auto& e : config_)
    if (e.name == name) e.value = value;
  return CameraStatus::Ok();
}

// The flash where the photographer holds it: the rig's next hand-held position, or the one asked
// for (its power varies from shot to shot as a real flash's does).
RigShot VirtualCamera::NextFlash(CameraStatus* status) {
  ConfigEntry held;
  GetConfig(kFlashPositionSetting, &held);
  RigShot shot;
  if (held.value == kFlashHandHeld) {
    const int available = int(scene_->shots.size());
    if (next_flash_ >= available)
      *status = CameraStatus::Error(CameraError::kCardFull, "virtual camera: the rig has only " + std::to_string(available) +
                                                                " hand-held flash positions (raise shots= in the port, "
                                                                "or set flashposition=x,y,z)");
    else
      shot = scene_->shots[next_flash_];
    return shot;
  }
  ParsePosition(held.value, &shot.light_m);
  std::mt19937_64 rng(seed_ * 1'000'003 + taken_.size());
  shot.power = 1.0 + 0.15 * std::uniform_real_distribution<double>(-1, 1)(rng);
  // A person holds the flash near the asked position, not at it.
  std::normal_distribution<double> miss(0.0, follow_error_m_);
  if (follow_error_m_ > 0) shot.light_m += Eigen::Vector3d(miss(rng), miss(rng), miss(rng));
  return shot;
}

CameraStatus VirtualCamera::Render(CameraFilePath* on_card) {
  if (closed_) return CameraStatus::Error(CameraError::kGone, "virtual camera: closed");
  ConfigEntry subject;
  GetConfig("subject", &subject);
  const bool flash = subject.value == "flash";
  const int index = flash ? int(taken_.size()) : next_calib_;
  CameraStatus status;
  RigShot shot;
  if (flash) {
    shot = NextFlash(&status);
  } else if (next_calib_ >= int(scene_->calib_shots.size())) {
    status = CameraStatus::Error(CameraError::kCardFull, "virtual camera: the rig has only " +
                                                             std::to_string(scene_->calib_shots.size()) +
                                                             " checkerboard shots (raise calib-shots= in the port)");
  }
  if (!status.ok()) return status;
  if (!renderer_) {
    renderer_ = std::make_unique<RigRenderer>(*scene_, *material_);
    renderer_->Prepare();
  }
  // The same streams and clock as `mesocap simulate` (checkerboard shots first on its clock);
  // flash shots are numbered in the order taken, hand-held or not.
  Image image = flash ? renderer_->RenderFlashLinear(shot) : renderer_->RenderCalibLinear(index);
  renderer_->ApplySensor(&image, flash ? uint64_t(index) : 1'000'000 + uint64_t(index));
  const int clock = flash ? int(scene_->calib_shots.size()) + index : index;
  char name[64];
  std::snprintf(name, sizeof name, "%s_%04d%s", flash ? "shot" : "calib", index + 1, ExtensionForFormat(format_).c_str());
  const fs::path file = card_ / "DCIM" / "100VIRT" / name;
  if (Status st = WriteImage(file, image, VirtualShotWriteOptions(format_, flash, clock)); !st.ok())
    return CameraStatus::Error(CameraError::kIo, "virtual camera: " + st.message());
  if (flash) {
    ConfigEntry held;
    GetConfig(kFlashPositionSetting, &held);
    if (held.value == kFlashHandHeld) ++next_flash_;
    shot.file = name;  // as on the card
    taken_.push_back(shot);
  } else {
    RigCalibShot taken = scene_->calib_shots[size_t(next_calib_)];
    taken.file = name;
    calib_taken_.push_back(taken);
    ++next_calib_;
  }
  *on_card = {"/DCIM/100VIRT", name};
  return CameraStatus::Ok();
}

Json VirtualCamera::TruthOfShotsTaken(const std::map<std::string, std::string>& session_files) const {
  RigScene truth = *scene_;
  truth.shots.clear();
  truth.calib_shots.clear();
  const auto renamed = [&](auto shot) -> std::optional<decltype(shot)> {
    const auto it = session_files.find(shot.file);
    if (it == session_files.end()) return std::nullopt;
    shot.file = it->second;
    return shot;
  };
  for (const RigShot& shot : taken_)
    if (auto named = renamed(shot)) truth.shots.push_back(*named);
  for (const RigCalibShot& shot : calib_taken_)
    if (auto named = renamed(shot)) truth.calib_shots.push_back(*named);
  return TruthToJson(truth);
}

CameraStatus VirtualCamera::Capture(CameraFilePath* on_card) { return Render(on_card); }

CameraStatus VirtualCamera::TriggerCapture() {
  CameraFilePath path;
  if (CameraStatus st = Render(&path); !st.ok()) return st;
  events_.push_back(path);
  return CameraStatus::Ok();
}

CameraStatus VirtualCamera::WaitForFileAdded(double timeout_s, CameraFilePath* added, bool* got) {
  if (closed_) return CameraStatus::Error(CameraError::kGone, "virtual camera: closed");
  *got = !events_.empty();
  if (*got) {
    *added = events_.front();
    events_.pop_front();
  } else if (timeout_s > 0) {
    ::usleep(useconds_t(std::min(timeout_s, 0.2) * 1e6));  // no photographer: nothing arrives
  }
  return CameraStatus::Ok();
}

CameraStatus VirtualCamera::Download(const CameraFilePath& on_card, const fs::path& dest, int64_t* bytes,
                                     int64_t* expected_bytes) {
  if (closed_) return CameraStatus::Error(CameraError::kGone, "virtual camera: closed");
  const fs::path src = card_ / on_card.ToString().substr(1);
  std::error_code ec;
  fs::copy_file(src, dest, fs::copy_options::overwrite_existing, ec);
  if (ec) {
    const bool full = ec == std::errc::no_space_on_device;
    return CameraStatus::Error(full ? CameraError::kDiskFull : CameraError::kIo,
                               dest.string() + ": download of " + on_card.ToString() + " failed: " + ec.message());
  }
  *bytes = int64_t(fs::file_size(dest, ec));
  *expected_bytes = int64_t(fs::file_size(src, ec));
  return CameraStatus::Ok();
}

CameraStatus VirtualCamera::DeleteFile(const CameraFilePath& on_card) {
  std::error_code ec;
  fs::remove(card_ / on_card.ToString().substr(1), ec);
  return CameraStatus::Ok();
}

}  // namespace mesocap

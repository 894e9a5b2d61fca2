#include "capture/fake_camera.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <thread>

namespace mesocap {
namespace fs = std::filesystem;

namespace {

std::string Joined(const std::vector<std::string>& items) {
  std::string out;
  for (size_t i = 0; i < items.size(); ++i) out += (i ? ", " : "") + items[i];
  return out;
}

}  // namespace

FakeCamera::FakeCamera(FakeCameraOptions options) : options_(std::move(options)) {
  busy_left_ = options_.busy_at;
  corrupt_left_ = options_.corrupt_download_at;
  config_ = {
      {"iso", "ISO Speed", "radio", "200", {"100", "200", "400", "800", "1600"}, false},
      {"shutterspeed", "Shutter Speed", "radio", "1/125", {"1/60", "1/125", "1/250", "1/500"}, false},
      {"f-number", "F-Number", "radio", "f/8", {"f/4", "f/5.6", "f/8", "f/11", "f/16"}, false},
      {"flashmode", "Flash Mode", "radio", "on", {"on", "off"}, false},
      {"capturetarget", "Capture Target", "radio", "Internal RAM", {"Internal RAM", "Memory card"}, false},
      {"imageformat", "Image Format", "radio", "JPEG Fine", {"JPEG Fine", "NEF (Raw)"}, false},
      {"batterylevel", "Battery Level", "text", "100%", {}, true},
  };
}

CameraStatus FakeCamera::Gone() const {
  return CameraStatus::Error(CameraError::kGone, options_.model + " on " + options_.port +
                                                     ": camera not found (unplugged or switched off)");
}

CameraStatus FakeCamera::ListConfig(std::vector<ConfigEntry>* entries) {
  if (closed_ || (options_.disconnect_after >= 0 && captures_ >= options_.disconnect_after)) return Gone();
  *entries = config_;
  return CameraStatus::Ok();
}

CameraStatus FakeCamera::GetConfig(const std::string& name, ConfigEntry* entry) {
  if (closed_ || (options_.disconnect_after >= 0 && captures_ >= options_.disconnect_after)) return Gone();
  const std::string key = name == "aperture" ? "f-number" : name;
  for (const auto& e : config_)
    if (e.name == key) {
      *entry = e;
      return CameraStatus::Ok();
    }
  std::vector<std::string> names;
  for (const auto& e : config_)
    if (!e.read_only) names.push_back(e.name);
  return CameraStatus::Error(CameraError::kBadSetting,
                             options_.model + ": no setting '" + name + "'; settable keys: " + Joined(names));
}

CameraStatus FakeCamera::SetConfig(const std::string& name, const std::string& value) {
  ConfigEntry found;
  if (auto st = GetConfig(name, &found); !st.ok()) return st;
  for (auto& e : config_) {
    if (e.name != found.name) continue;
    if (e.read_only) return CameraStatus::Error(CameraError::kBadSetting, options_.model + ": setting '" + e.name + "' is read-only");
    if (std::find(e.choices.begin(), e.choices.end(), value) == e.choices.end())
      return CameraStatus::Error(CameraError::kBadSetting, options_.model + ": setting '" + e.name + "': '" + value +
                                                               "' is not a valid value; choices: " + Joined(e.choices));
    e.value = value;
  }
  return CameraStatus::Ok();
}

CameraStatus FakeCamera::TakePicture(CameraFilePath* on_card) {
  if (closed_) return Gone();
  ++capture_attempts_;
  const int number = captures_ + 1;
  if (options_.disconnect_after >= 0 && captures_ >= options_.disconnect_after) return Gone();
  if (auto it = busy_left_.find(number); it != busy_left_.end() && it->second > 0) {
    --it->second;
    return CameraStatus::Error(CameraError::kBusy, options_.model + ": capture failed: camera is busy");
  }
  if (options_.card_capacity >= 0 && captures_ >= options_.card_capacity)
    return CameraStatus::Error(CameraError::kCardFull, options_.model + ": capture failed: the card is full");
  if (options_.photos.empty())
    return CameraStatus::Error(CameraError::kOther, options_.model + ": no photos to serve");
  if (options_.capture_delay_s > 0)
    std::this_thread::sleep_for(std::chrono::duration<double>(options_.capture_delay_s));
  captures_ = number;
  const fs::path& source = options_.photos[size_t(number - 1) % options_.photos.size()];
  char name[32];
  std::snprintf(name, sizeof name, "FAKE%04d%s", number, source.extension().string().c_str());
  on_card->folder = "/DCIM/100FAKE";
  on_card->name = name;
  card_[name] = source;
  capture_number_[name] = number;
  return CameraStatus::Ok();
}

CameraStatus FakeCamera::Capture(CameraFilePath* on_card) { return TakePicture(on_card); }

CameraStatus FakeCamera::TriggerCapture() {
  CameraFilePath path;
  if (auto st = TakePicture(&path); !st.ok()) return st;
  pending_events_.push_back(path);
  return CameraStatus::Ok();
}

CameraStatus FakeCamera::WaitForFileAdded(double timeout_s, CameraFilePath* added, bool* got) {
  *got = false;
  if (closed_) return Gone();
  if (!pending_events_.empty()) {
    *added = pending_events_.front();
    pending_events_.erase(pending_events_.begin());
    *got = true;
    return CameraStatus::Ok();
  }
  if (options_.disconnect_after >= 0 && captures_ >= options_.disconnect_after) return Gone();
  std::this_thread::sleep_for(std::chrono::duration<double>(std::min(timeout_s, 0.05)));
  return CameraStatus::Ok();
}

fs::path FakeCamera::SourceOf(const CameraFilePath& on_card) const {
  auto it = card_.find(on_card.name);
  return it == card_.end() ? fs::path() : it->second;
}

CameraStatus FakeCamera::Download(const CameraFilePath& on_card, const fs::path& dest, int64_t* bytes,
                                  int64_t* expected_bytes) {
  *bytes = 0;
  *expected_bytes = -1;
  if (closed_) return Gone();
  auto it = card_.find(on_card.name);
  if (it == card_.end())
    return CameraStatus::Error(CameraError::kOther, options_.model + ": no file " + on_card.ToString() + " on the card");
  const int number = capture_number_[on_card.name];
  if (options_.disk_full_at.count(number))
    return CameraStatus::Error(CameraError::kDiskFull, dest.string() + ": write failed: No space left on device");

  std::ifstream in(it->second, std::ios::binary);
  std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof())
    return CameraStatus::Error(CameraError::kOther, it->second.string() + ": cannot read the photo to serve");
  *expected_bytes = int64_t(data.size());
  if (auto c = corrupt_left_.find(number); c != corrupt_left_.end() && c->second > 0) {
    --c->second;
    data.resize(data.size() / 2);  // a transfer cut short
    if (options_.corrupt_keeps_size) *expected_bytes = int64_t(data.size());
  }
  std::ofstream out(dest, std::ios::binary | std::ios::trunc);
  out.write(data.data(), std::streamsize(data.size()));
  out.close();
  if (!out) return CameraStatus::Error(CameraError::kOther, dest.string() + ": write failed");
  ++downloads_;
  *bytes = int64_t(data.size());
  return CameraStatus::Ok();
}

CameraStatus FakeCamera::DeleteFile(const CameraFilePath& on_card) {
  if (closed_) return Gone();
  if (card_.erase(on_card.name) == 0)
    return CameraStatus::Error(CameraError::kOther, options_.model + ": no file " + on_card.ToString() + " on the card");
  return CameraStatus::Ok();
}

}  // namespace mesocap

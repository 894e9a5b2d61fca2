#include "capture/gphoto2_camera.h"

#include <fcntl.h>
#include <gphoto2/gphoto2.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <functional>

#include "core/text_format.h"

namespace mesocap {
namespace fs = std::filesystem;

struct Gphoto2Camera::Context {
  GPContext* context = nullptr;
  std::string last_error;  // the newest message libgphoto2 reported through gp_context_error

  Context() {
    context = gp_context_new();
    gp_context_set_error_func(
        context, [](GPContext*, const char* text, void* self) { static_cast<Context*>(self)->last_error = text; },
        this);
  }
  ~Context() {
    if (context) gp_context_unref(context);
  }
  std::string TakeError() {
    std::string e;
    e.swap(last_error);
    while (!e.empty() && std::isspace(static_cast<unsigned char>(e.back()))) e.pop_back();
    return e;
  }
};

namespace {

std::string Joined(const std::vector<std::string>& items, size_t max_items = 60) {
  std::string out;
  for (size_t i = 0; i < items.size() && i < max_items; ++i) out += (i ? ", " : "") + items[i];
  if (items.size() > max_items) out += ", ... (" + std::to_string(items.size() - max_items) + " more)";
  return out;
}

CameraError ErrorOf(int result, const std::string& context_message) {
  const std::string m = Lower(context_message);
  // PTP "Store Full" in a response, or the store-full event during a capture ("Camera
  // memorycard ran full during capture.", reported as GP_ERROR_NO_MEMORY).
  if (m.find("store full") != std::string::npos || m.find("storefull") != std::string::npos ||
      m.find("card full") != std::string::npos || m.find("ran full") != std::string::npos)
    return CameraError::kCardFull;
  switch (result) {
    case GP_OK: return CameraError::kOk;
    case GP_ERROR_CAMERA_BUSY: return CameraError::kBusy;
    case GP_ERROR_NO_SPACE: return CameraError::kCardFull;
    case GP_ERROR_NOT_SUPPORTED: return CameraError::kNotSupported;
    case GP_ERROR_TIMEOUT: return CameraError::kIo;
    case GP_ERROR_IO_USB_FIND:
    case GP_ERROR_MODEL_NOT_FOUND:
    case GP_ERROR_IO_INIT: return CameraError::kGone;
    case GP_ERROR_IO:
    case GP_ERROR_IO_READ:
    case GP_ERROR_IO_WRITE:
    case GP_ERROR_IO_UPDATE:
    case GP_ERROR_IO_USB_CLEAR_HALT:
    case GP_ERROR_CORRUPTED_DATA: return CameraError::kIo;
    default: return CameraError::kOther;
  }
}

// Free bytes for unprivileged writers on the file system holding `dir`; -1 when unknown.
int64_t FreeBytes(const fs::path& dir) {
  struct statvfs st {};
  if (::statvfs(dir.empty() ? "." : dir.c_str(), &st) != 0) return -1;
  return int64_t(st.f_bavail) * int64_t(st.f_frsize);
}

// Visits every leaf widget (not windows, sections or buttons) below `w`.
void ForEachLeaf(CameraWidget* w, const std::function<void(CameraWidget*)>& fn) {
  CameraWidgetType type;
  if (gp_widget_get_type(w, &type) < GP_OK) return;
  if (type == GP_WIDGET_WINDOW || type == GP_WIDGET_SECTION) {
    const int n = gp_widget_count_children(w);
    for (int i = 0; i < n; ++i) {
      CameraWidget* child = nullptr;
      if (gp_widget_get_child(w, i, &child) == GP_OK) ForEachLeaf(child, fn);
    }
    return;
  }
  if (type != GP_WIDGET_BUTTON) fn(w);
}

std::string FormatFloat(float v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", double(v));
  return buf;
}

ConfigEntry EntryOf(CameraWidget* w) {
  ConfigEntry e;
  const char* text = nullptr;
  if (gp_widget_get_name(w, &text) == GP_OK && text) e.name = text;
  if (gp_widget_get_label(w, &text) == GP_OK && text) e.label = text;
  int ro = 0;
  gp_widget_get_readonly(w, &ro);
  e.read_only = ro != 0;
  CameraWidgetType type = GP_WIDGET_TEXT;
  gp_widget_get_type(w, &type);
  switch (type) {
    case GP_WIDGET_TEXT:
    case GP_WIDGET_RADIO:
    case GP_WIDGET_MENU: {
      e.type = type == GP_WIDGET_TEXT ? "text" : type == GP_WIDGET_RADIO ? "radio" : "menu";
      const char* v = nullptr;
      if (gp_widget_get_value(w, &v) == GP_OK && v) e.value = v;
      if (type != GP_WIDGET_TEXT) {
        const int n = gp_widget_count_choices(w);
        for (int i = 0; i < n; ++i)
          if (gp_widget_get_choice(w, i, &text) == GP_OK && text) e.choices.push_back(text);
      }
      break;
    }
    case GP_WIDGET_RANGE: {
      e.type = "range";
      float v = 0, lo = 0, hi = 0, step = 0;
      if (gp_widget_get_value(w, &v) == GP_OK) e.value = FormatFloat(v);
      if (gp_widget_get_range(w, &lo, &hi, &step) == GP_OK)
        e.choices.push_back(FormatFloat(lo) + ".." + FormatFloat(hi) + " step " + FormatFloat(step));
      break;
    }
    case GP_WIDGET_TOGGLE:
    case GP_WIDGET_DATE: {
      e.type = type == GP_WIDGET_TOGGLE ? "toggle" : "date";
      int v = 0;
      if (gp_widget_get_value(w, &v) == GP_OK) e.value = std::to_string(v);
      if (type == GP_WIDGET_TOGGLE) e.choices = {"0", "1"};
      break;
    }
    default: e.type = "other";
  }
  return e;
}

// Other names bodies use for the same setting.
std::vector<std::string> AliasesOf(const std::string& name) {
  if (name == "aperture") return {"f-number"};
  if (name == "f-number" || name == "fnumber") return {"f-number", "aperture"};
  if (name == "iso") return {"iso", "isospeed"};
  if (name == "shutter" || name == "shutter-speed") return {"shutterspeed", "shutterspeed2"};
  if (name == "format") return {"imageformat", "imagequality"};
  return {};
}

// RAII for a widget tree.
struct WidgetTree {
  CameraWidget* root = nullptr;
  ~WidgetTree() {
    if (root) gp_widget_free(root);
  }
};

}  // namespace

Gphoto2Camera::Gphoto2Camera(_Camera* camera, std::unique_ptr<Context> context, CameraInfo info)
    : camera_(camera), context_(std::move(context)), info_(std::move(info)) {}

Gphoto2Camera::~Gphoto2Camera() { Close(); }

void Gphoto2Camera::Close() {
  if (!camera_) return;
  gp_camera_exit(camera_, context_->context);
  gp_camera_unref(camera_);
  camera_ = nullptr;
}

CameraStatus Gphoto2Camera::Check(int result, const std::string& what) const {
  if (result >= GP_OK) return CameraStatus::Ok();
  std::string detail = context_->TakeError();
  std::string message = info_.model + " on " + info_.port + ": " + what + " failed: " + gp_result_as_string(result);
  if (!detail.empty()) message += " (" + detail + ")";
  return CameraStatus::Error(ErrorOf(result, detail), message);
}

StatusOr<std::vector<CameraInfo>> Gphoto2Camera::Detect() {
  Context ctx;
  CameraList* list = nullptr;
  gp_list_new(&list);
  const int n = gp_camera_autodetect(list, ctx.context);
  if (n < GP_OK) {
    gp_list_free(list);
    return Status::Error(std::string("libgphoto2 camera detection failed: ") + gp_result_as_string(n) +
                         (ctx.last_error.empty() ? "" : " (" + ctx.TakeError() + ")"));
  }
  std::vector<CameraInfo> cameras;
  for (int i = 0; i < gp_list_count(list); ++i) {
    const char *name = nullptr, *value = nullptr;
    gp_list_get_name(list, i, &name);
    gp_list_get_value(list, i, &value);
    cameras.push_back({name ? name : "", value ? value : ""});
  }
  gp_list_free(list);
  return cameras;
}

StatusOr<std::unique_ptr<Gphoto2Camera>> Gphoto2Camera::Open(const std::string& model, const std::string& port) {
  CameraInfo chosen{model, port};
  if (model.empty() || port.empty()) {
    auto detected = Detect();
    if (!detected.ok()) return detected.status();
    std::vector<CameraInfo> matches;
    for (const auto& c : *detected)
      if ((model.empty() || Lower(c.model) == Lower(model)) && (port.empty() || c.port == port)) matches.push_back(c);
    std::vector<std::string> listed;
    for (const auto& c : *detected) listed.push_back(c.model + " on " + c.port);
    const std::string wanted = model.empty() && port.empty() ? "a camera"
                               : "a camera" + (model.empty() ? "" : " '" + model + "'") +
                                     (port.empty() ? "" : " on port '" + port + "'");
    if (matches.empty())
      return Status::Error("no " + wanted.substr(2) + " detected by libgphoto2" +
                           (listed.empty() ? " (is it connected, switched on and not mounted by another program?)"
                                           : "; detected: " + Joined(listed)));
    if (matches.size() > 1)
      return Status::Error("several cameras match; choose one with --camera MODEL and --port PORT: " + Joined(listed));
    chosen = matches.front();
  }

  auto context = std::make_unique<Context>();
  ::Camera* camera = nullptr;
  if (int r = gp_camera_new(&camera); r < GP_OK)
    return Status::Error(std::string("libgphoto2: cannot create a camera: ") + gp_result_as_string(r));
  auto fail = [&](const std::string& what, int r) -> Status {
    std::string detail = context->TakeError();
    gp_camera_unref(camera);
    return Status::Error(chosen.model + " on " + chosen.port + ": " + what + ": " + gp_result_as_string(r) +
                         (detail.empty() ? "" : " (" + detail + ")"));
  };

  // The driver for the model.
  CameraAbilitiesList* abilities_list = nullptr;
  gp_abilities_list_new(&abilities_list);
  int r = gp_abilities_list_load(abilities_list, context->context);
  int index = r < GP_OK ? r : gp_abilities_list_lookup_model(abilities_list, chosen.model.c_str());
  CameraAbilities abilities;
  if (index >= GP_OK) r = gp_abilities_list_get_abilities(abilities_list, index, &abilities);
  gp_abilities_list_free(abilities_list);
  if (index < GP_OK) return fail("no libgphoto2 driver for this model (see `mesocap cameras`)", index);
  if (r < GP_OK) return fail("cannot read the driver's abilities", r);
  if ((r = gp_camera_set_abilities(camera, abilities)) < GP_OK) return fail("cannot select the driver", r);

  // The port.
  GPPortInfoList* ports = nullptr;
  gp_port_info_list_new(&ports);
  r = gp_port_info_list_load(ports);
  index = r < GP_OK ? r : gp_port_info_list_lookup_path(ports, chosen.port.c_str());
  GPPortInfo port_info;
  if (index >= GP_OK) r = gp_port_info_list_get_info(ports, index, &port_info);
  if (index >= GP_OK && r >= GP_OK) r = gp_camera_set_port_info(camera, port_info);
  gp_port_info_list_free(ports);
  if (index < GP_OK) return fail("no such port", index);
  if (r < GP_OK) return fail("cannot select the port", r);

  if ((r = gp_camera_init(camera, context->context)) < GP_OK)
    return fail("cannot open the camera (busy in another program, or switched off?)", r);
  return std::unique_ptr<Gphoto2Camera>(new Gphoto2Camera(camera, std::move(context), chosen));
}

CameraStatus Gphoto2Camera::ListConfig(std::vector<ConfigEntry>* entries) {
  entries->clear();
  if (!camera_) return CameraStatus::Error(CameraError::kGone, info_.model + ": camera is closed");
  WidgetTree tree;
  if (auto st = Check(gp_camera_get_config(camera_, &tree.root, context_->context), "reading the configuration");
      !st.ok())
    return st;
  ForEachLeaf(tree.root, [&](CameraWidget* w) { entries->push_back(EntryOf(w)); });
  return CameraStatus::Ok();
}

CameraStatus Gphoto2Camera::GetConfig(const std::string& name, ConfigEntry* entry) {
  if (!camera_) return CameraStatus::Error(CameraError::kGone, info_.model + ": camera is closed");
  WidgetTree tree;
  if (auto st = Check(gp_camera_get_config(camera_, &tree.root, context_->context), "reading the configuration");
      !st.ok())
    return st;
  std::vector<std::string> candidates = {name};
  for (const auto& a : AliasesOf(Lower(name))) candidates.push_back(a);
  for (const auto& n : candidates) {
    CameraWidget* w = nullptr;
    if (gp_widget_get_child_by_name(tree.root, n.c_str(), &w) == GP_OK && w) {
      *entry = EntryOf(w);
      return CameraStatus::Ok();
    }
  }
  std::vector<std::string> names;
  ForEachLeaf(tree.root, [&](CameraWidget* w) {
    const char* n = nullptr;
    int ro = 0;
    gp_widget_get_readonly(w, &ro);
    if (gp_widget_get_name(w, &n) == GP_OK && n && !ro) names.push_back(n);
  });
  std::sort(names.begin(), names.end());
  return CameraStatus::Error(CameraError::kBadSetting, info_.model + ": no setting '" + name +
                                                           "'; settable keys: " + Joined(names, 400));
}

CameraStatus Gphoto2Camera::SetConfig(const std::string& name, const std::string& value) {
  if (!camera_) return CameraStatus::Error(CameraError::kGone, info_.model + ": camera is closed");
  ConfigEntry entry;
  if (auto st = GetConfig(name, &entry); !st.ok()) return st;  // lists the valid keys
  const std::string where = info_.model + ": setting '" + entry.name + "'";
  if (entry.read_only) return CameraStatus::Error(CameraError::kBadSetting, where + " is read-only");

  WidgetTree tree;
  if (auto st = Check(gp_camera_get_config(camera_, &tree.root, context_->context), "reading the configuration");
      !st.ok())
    return st;
  CameraWidget* w = nullptr;
  if (gp_widget_get_child_by_name(tree.root, entry.name.c_str(), &w) != GP_OK || !w)
    return CameraStatus::Error(CameraError::kOther, where + " vanished from the configuration");

  int r = GP_OK;
  if (entry.type == "radio" || entry.type == "menu") {
    std::string chosen;
    for (const auto& c : entry.choices)
      if (c == value) chosen = c;
    if (chosen.empty())
      for (const auto& c : entry.choices)
        if (Lower(c) == Lower(value)) chosen = c;
    if (chosen.empty())
      return CameraStatus::Error(CameraError::kBadSetting,
                                 where + ": '" + value + "' is not a valid value; choices: " + Joined(entry.choices, 400));
    r = gp_widget_set_value(w, chosen.c_str());
  } else if (entry.type == "text") {
    r = gp_widget_set_value(w, value.c_str());
  } else if (entry.type == "range") {
    char* end = nullptr;
    const float v = std::strtof(value.c_str(), &end);
    float lo = 0, hi = 0, step = 0;
    gp_widget_get_range(w, &lo, &hi, &step);
    if (end == value.c_str() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi)
      return CameraStatus::Error(CameraError::kBadSetting, where + ": '" + value + "' is not a number in " +
                                                               (entry.choices.empty() ? "range" : entry.choices[0]));
    r = gp_widget_set_value(w, &v);
  } else if (entry.type == "toggle" || entry.type == "date") {
    char* end = nullptr;
    const long v = std::strtol(value.c_str(), &end, 10);
    if (end == value.c_str() || *end != '\0' || (entry.type == "toggle" && v != 0 && v != 1))
      return CameraStatus::Error(CameraError::kBadSetting, where + ": '" + value + "' is not " +
                                                               (entry.type == "toggle" ? "0 or 1" : "a Unix time"));
    const int iv = int(v);
    r = gp_widget_set_value(w, &iv);
  } else {
    return CameraStatus::Error(CameraError::kBadSetting, where + " has a type mesocap cannot set");
  }
  if (auto st = Check(r, "setting '" + entry.name + "' to '" + value + "'"); !st.ok()) return st;
  return Check(gp_camera_set_config(camera_, tree.root, context_->context),
               "setting '" + entry.name + "' to '" + value + "'");
}

CameraStatus Gphoto2Camera::Capture(CameraFilePath* on_card) {
  if (!camera_) return CameraStatus::Error(CameraError::kGone, info_.model + ": camera is closed");
  ::CameraFilePath path{};
  if (auto st = Check(gp_camera_capture(camera_, GP_CAPTURE_IMAGE, &path, context_->context), "capture"); !st.ok())
    return st;
  on_card->folder = path.folder;
  on_card->name = path.name;
  return CameraStatus::Ok();
}

CameraStatus Gphoto2Camera::TriggerCapture() {
  if (!camera_) return CameraStatus::Error(CameraError::kGone, info_.model + ": camera is closed");
  return Check(gp_camera_trigger_capture(camera_, context_->context), "trigger");
}

CameraStatus Gphoto2Camera::WaitForFileAdded(double timeout_s, CameraFilePath* added, bool* got) {
  *got = false;
  if (!camera_) return CameraStatus::Error(CameraError::kGone, info_.model + ": camera is closed");
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout_s));
  while (true) {
    const double left_s = std::chrono::duration<double>(deadline - Clock::now()).count();
    const int timeout_ms = std::max(0, int(std::lround(left_s * 1000)));
    CameraEventType type = GP_EVENT_UNKNOWN;
    void* data = nullptr;
    const int r = gp_camera_wait_for_event(camera_, timeout_ms, &type, &data, context_->context);
    if (auto st = Check(r, "waiting for events"); !st.ok()) {
      std::free(data);
      return st;
    }
    if (type == GP_EVENT_FILE_ADDED && data) {
      const auto* path = static_cast<::CameraFilePath*>(data);
      added->folder = path->folder;
      added->name = path->name;
      std::free(data);
      *got = true;
      return CameraStatus::Ok();
    }
    std::free(data);  // FOLDER_ADDED, CAPTURE_COMPLETE, UNKNOWN ... are not shots
    if (type == GP_EVENT_TIMEOUT || Clock::now() >= deadline) return CameraStatus::Ok();
  }
}

CameraStatus Gphoto2Camera::Download(const CameraFilePath& on_card, const fs::path& dest, int64_t* bytes,
                                     int64_t* expected_bytes) {
  *bytes = 0;
  *expected_bytes = -1;
  if (!camera_) return CameraStatus::Error(CameraError::kGone, info_.model + ": camera is closed");
  const std::string what = "downloading " + on_card.ToString() + " to " + dest.string();

  CameraFileInfo file_info{};
  if (gp_camera_file_get_info(camera_, on_card.folder.c_str(), on_card.name.c_str(), &file_info,
                              context_->context) == GP_OK &&
      (file_info.file.fields & GP_FILE_INFO_SIZE))
    *expected_bytes = int64_t(file_info.file.size);
  context_->TakeError();  // a body without file info is not an error

  const int fd = ::open(dest.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) {
    const int e = errno;
    return CameraStatus::Error(e == ENOSPC ? CameraError::kDiskFull : CameraError::kOther,
                               dest.string() + ": cannot create: " + std::strerror(e));
  }
  CameraFile* file = nullptr;
  if (int r = gp_file_new_from_fd(&file, fd); r < GP_OK) {
    ::close(fd);
    return Check(r, what);
  }
  const int r = gp_camera_file_get(camera_, on_card.folder.c_str(), on_card.name.c_str(), GP_FILE_TYPE_NORMAL, file,
                                   context_->context);
  gp_file_unref(file);  // closes fd
  struct stat st {};
  if (::stat(dest.c_str(), &st) == 0) *bytes = int64_t(st.st_size);
  if (r < GP_OK) {
    CameraStatus status = Check(r, what);
    const int64_t free_bytes = FreeBytes(dest.parent_path());
    if (free_bytes >= 0 && (free_bytes < (1 << 20) || (*expected_bytes > 0 && free_bytes < *expected_bytes)))
      return CameraStatus::Error(CameraError::kDiskFull, dest.string() + ": no space left on the disk (" +
                                                             status.message + ")");
    return status;
  }
  return CameraStatus::Ok();
}

CameraStatus Gphoto2Camera::DeleteFile(const CameraFilePath& on_card) {
  if (!camera_) return CameraStatus::Error(CameraError::kGone, info_.model + ": camera is closed");
  return Check(gp_camera_file_delete(camera_, on_card.folder.c_str(), on_card.name.c_str(), context_->context),
               "deleting " + on_card.ToString());
}

}  // namespace mesocap

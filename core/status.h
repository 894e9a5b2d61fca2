// Status and StatusOr: the second tier of failure (bad data or I/O). The message names the file
// and what was wrong; library code returns these instead of aborting.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

namespace mesocap {

class Status {
 public:
  Status() = default;
  static Status Ok() { return Status(); }
  static Status Error(std::string message) { return Status(std::move(message)); }
  // The user stopped the work (Ctrl-C, core/cancel.h): a status of its own, so every caller can
  // tell it from a failure without reading the message (commands exit 3 for it).
  static Status Cancelled() {
    Status s("cancelled");
    s.cancelled_ = true;
    return s;
  }

  bool ok() const { return !message_.has_value(); }
  bool cancelled() const { return cancelled_; }
  // The same status with `context` before its message ("stage reconstruct: ..."), still cancelled
  // if it was.
  Status WithContext(const std::string& context) const {
    if (ok()) return *this;
    Status s(context + *message_);
    s.cancelled_ = cancelled_;
    return s;
  }
  const std::string& message() const {
    static const std::string kOk = "ok";
    return message_ ? *message_ : kOk;
  }

 private:
  explicit Status(std::string message) : message_(std::move(message)) {}
  std::optional<std::string> message_;
  bool cancelled_ = false;
};

template <typename T>
class StatusOr {
 public:
  StatusOr(T value) : value_(std::move(value)) {}  // NOLINT: implicit by design
  StatusOr(Status status) : status_(std::move(status)) {  // NOLINT
    if (status_.ok()) throw std::logic_error("StatusOr built from an ok Status without a value");
  }

  bool ok() const { return value_.has_value(); }
  const Status& status() const { return status_; }
  T& value() {
    if (!value_) throw std::runtime_error(status_.message());
    return *value_;
  }
  const T& value() const {
    if (!value_) throw std::runtime_error(status_.message());
    return *value_;
  }
  T& operator*() { return value(); }
  const T& operator*() const { return value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }

 private:
  Status status_;
  std::optional<T> value_;
};

// A broken precondition (programming error, impossible option that slipped past Check()).
// Thrown, and caught only where the commands module runs a command (app/commands_module.cc).
#define MESOCAP_CHECK(cond, msg)                                                          \
  do {                                                                                    \
    if (!(cond))                                                                          \
      throw std::logic_error(std::string(__FILE__) + ":" + std::to_string(__LINE__) +     \
                             ": check failed: " #cond ": " + std::string(msg));          \
  } while (0)

// Returns early from a function returning Status/StatusOr when `expr` failed.
#define MESOCAP_RETURN_IF_ERROR(expr)        \
  do {                                       \
    const ::mesocap::Status _st = (expr);    \
    if (!_st.ok()) return _st;               \
  } while (0)

}  // namespace mesocap

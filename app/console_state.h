// The capture console's state (`mesocap console`, docs/console.md): one JSON document that the page
// and scripts read whole (GET /api/state), changed only through Update, which also appends an
// event to a numbered log that every event stream (GET /api/events) sends in order, so each
// client sees every change, also one that came while it was busy writing the previous.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "core/json.h"

namespace mesocap::app {

struct ConsoleEvent {
  int64_t id = 0;    // 1, 2, ... in the order of the changes
  std::string data;  // one line of JSON: {"type": "shot", "version": id, ...}
};

class ConsoleState {
 public:
  explicit ConsoleState(Json initial);

  // Changes the state under the lock, then logs `event` (an object with at least "type") with
  // the new version and wakes every stream.
  void Update(const std::function<void(Json& state)>& change, Json event);
  // The state as of now, with "version": the id of the last event it includes.
  Json Snapshot() const;
  int64_t version() const;

  // The events after `after` (oldest first), waiting up to `wait` for one; empty when none came
  // or the state is closed. A stream that fell behind the log's bound gets a "resync" event.
  std::vector<ConsoleEvent> EventsAfter(int64_t after, std::chrono::milliseconds wait) const;
  // Ends every wait (the console is stopping); later waits return at once.
  void Close();
  bool closed() const;

 private:
  static constexpr size_t kKeptEvents = 4096;
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  Json state_;
  std::deque<ConsoleEvent> events_;
  int64_t version_ = 0;
  bool closed_ = false;
};

// The shot whose "file" is `file` in the state's "shots", or null.
Json* FindShot(Json& state, const std::string& file);

}  // namespace mesocap::app

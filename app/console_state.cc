#include "app/console_state.h"

namespace mesocap::app {

ConsoleState::ConsoleState(Json initial) : state_(std::move(initial)) { state_["version"] = 0; }

void ConsoleState::Update(const std::function<void(Json& state)>& change, Json event) {
  {
    std::lock_guard<std::mutex> hold(mutex_);
    change(state_);
    ++version_;
    state_["version"] = version_;
    event["version"] = version_;
    // Text from a camera or a child's output may not be UTF-8: replaced, never thrown on.
    events_.push_back({version_, event.dump(-1, ' ', false, Json::error_handler_t::replace)});
    if (events_.size() > kKeptEvents) events_.pop_front();
  }
  changed_.notify_all();
}

Json ConsoleState::Snapshot() const {
  std::lock_guard<std::mutex> hold(mutex_);
  return state_;
}

int64_t ConsoleState::version() const {
  std::lock_guard<std::mutex> hold(mutex_);
  return version_;
}

std::vector<ConsoleEvent> ConsoleState::EventsAfter(int64_t after, std::chrono::milliseconds wait) const {
  std::unique_lock<std::mutex> hold(mutex_);
  changed_.wait_for(hold, wait, [&] { return closed_ || version_ > after; });
  std::vector<ConsoleEvent> out;
  if (closed_ || version_ <= after) return out;
  if (events_.empty() || events_.front().id > after + 1)  // dropped from the log: read the state anew
    return {{version_, Json{{"type", "resync"}, {"version", version_}}.dump(-1, ' ', false, Json::error_handler_t::replace)}};
  for (const ConsoleEvent& e : events_)
    if (e.id > after) out.push_back(e);
  return out;
}

void ConsoleState::Close() {
  {
    std::lock_guard<std::mutex> hold(mutex_);
    closed_ = true;
  }
  changed_.notify_all();
}

bool ConsoleState::closed() const {
  std::lock_guard<std::mutex> hold(mutex_);
  return closed_;
}

Json* FindShot(Json& state, const std::string& file) {
  if (!state.contains("shots")) return nullptr;
  for (Json& shot : state["shots"])
    if (shot.value("file", "") == file) return &shot;
  return nullptr;
}

}  // namespace mesocap::app

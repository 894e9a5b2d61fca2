// The capture console end to end on the virtual camera: an operator (this test) follows the
// page's suggestions through the API the page uses, while 20 event streams watch; undo; finish
// runs `process`; a kill -9 midway and --resume; review of a finished session.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <mutex>
#include <regex>
#include <set>
#include <thread>

#include "core/json.h"
#include "core/session_layout.h"
#include "tests/raw_http.h"
#include "tests/testing.h"

namespace mesocap {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

const std::string kCamera =
    "--camera virtual --port virtual:seed=41,width=1200,height=800,shots=40,calib-shots=10,follow-error=0.02";

struct RunningConsole {
  pid_t pid = 0;
  int port = 0;
  fs::path log;
};

// Starts `mesocap console ARGS --listen 127.0.0.1:0` and waits for the address it prints.
RunningConsole StartConsole(const std::string& args, const fs::path& log) {
  RunningConsole c;
  c.log = log;
  const std::string command =
      "exec " + testing::MesocapBinary() + " console " + args + " --listen 127.0.0.1:0 > " + log.string() + " 2>&1";
  c.pid = ::fork();
  if (c.pid == 0) {
    ::execl("/bin/sh", "sh", "-c", command.c_str(), nullptr);
    ::_exit(127);
  }
  const std::regex address(R"(on http://127\.0\.0\.1:(\d+)/)");
  for (const auto start = Clock::now(); Clock::now() - start < std::chrono::seconds(30);) {
    std::ifstream in(log);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    if (std::smatch m; std::regex_search(text, m, address)) {
      c.port = std::stoi(m[1]);
      return c;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return c;
}

int WaitForExit(pid_t pid, int timeout_s) {
  for (const auto start = Clock::now(); Clock::now() - start < std::chrono::seconds(timeout_s);) {
    int status = 0;
    if (::waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ::kill(pid, SIGKILL);
  ::waitpid(pid, nullptr, 0);
  return -1000;
}

Json State(int port) {
  const testing::RawReply reply = testing::LocalRequest(port, "GET /api/state");
  Json state = Json::parse(reply.body(), nullptr, false);
  return state.is_discarded() ? Json::object() : state;
}

int Post(int port, const std::string& path) { return testing::LocalRequest(port, "POST " + path).status; }

// The state once `ready` holds of it (null after `timeout_s`).
template <class Ready>
Json WaitFor(int port, Ready ready, int timeout_s = 60) {
  for (const auto start = Clock::now(); Clock::now() - start < std::chrono::seconds(timeout_s);) {
    const Json state = State(port);
    if (!state.empty() && ready(state)) return state;
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
  }
  return nullptr;
}

size_t Count(const Json& state, const std::string& kind, bool analysed) {
  size_t n = 0;
  for (const Json& shot : state["shots"]) n += shot["kind"] == kind && (!analysed || shot["analysed"].get<bool>());
  return n;
}

// A page's event stream read on its own thread: every event's JSON, as received.
class EventStream {
 public:
  explicit EventStream(int port) : fd_(testing::ConnectLocal(port, 120)) {
    const std::string request = "GET /api/events HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\n\r\n";
    ::send(fd_, request.data(), request.size(), MSG_NOSIGNAL);
    reader_ = std::thread([this] {
      char buffer[8192];
      std::string text;
      for (ssize_t n; (n = ::recv(fd_, buffer, sizeof buffer, 0)) > 0;) {
        text.append(buffer, size_t(n));
        for (size_t at; (at = text.find("data: ")) != std::string::npos;) {
          const size_t end = text.find("\n\n", at);
          if (end == std::string::npos) break;
          Json event = Json::parse(text.substr(at + 6, end - at - 6), nullptr, false);
          text.erase(0, end + 2);
          std::lock_guard<std::mutex> hold(mutex_);
          if (!event.is_discarded()) events_.push_back(event);
        }
      }
    });
  }
  ~EventStream() {
    ::shutdown(fd_, SHUT_RDWR);
    reader_.join();
    ::close(fd_);
  }
  std::vector<Json> events() const {
    std::lock_guard<std::mutex> hold(mutex_);
    return events_;
  }

 private:
  int fd_;
  std::thread reader_;
  mutable std::mutex mutex_;
  std::vector<Json> events_;
};

TEST(Console, AnOperatorFollowsTheSuggestionsUndoesAndFinishes) {
  const fs::path dir = testing::MakeTempDir(), session = dir / "s";
  RunningConsole console = StartConsole(session.string() + " " + kCamera +
                                            " --follow-guide --guide-after 5 --process-args "
                                            "'--slice-size 64 --btf-size 32 --btf-grid coarse'",
                                        dir / "console.log");
  ASSERT_GT(console.port, 0) << "no address printed; see " << console.log;
  const int port = console.port;
  std::vector<std::unique_ptr<EventStream>> watchers;
  for (int i = 0; i < 20; ++i) watchers.push_back(std::make_unique<EventStream>(port));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  for (size_t i = 1; i <= 10; ++i) {
    ASSERT_EQ(Post(port, "/api/calibration-shot"), 202);
    ASSERT_FALSE(WaitFor(port, [&](const Json& s) { return Count(s, "calib", true) == i; }).is_null()) << i;
  }
  // The operator waits for each shot's analysis, then holds the flash where it says (the virtual
  // photographer, within 2 cm).
  std::vector<double> percents;
  std::set<std::string> suggestions;
  double slowest_shot_s = 0;
  for (size_t i = 1; i <= 12; ++i) {
    const auto posted = Clock::now();
    ASSERT_EQ(Post(port, "/api/shot"), 202);
    ASSERT_FALSE(WaitFor(port, [&](const Json& s) { return Count(s, "shot", false) == i; }).is_null()) << i;
    slowest_shot_s = std::max(slowest_shot_s, std::chrono::duration<double>(Clock::now() - posted).count());
    const Json state = WaitFor(port, [&](const Json& s) { return Count(s, "shot", true) == i; });
    ASSERT_FALSE(state.is_null()) << i;
    if (!state["coverage"].is_null()) percents.push_back(state["coverage"]["percent"].get<double>());
    if (!state["next"].empty()) suggestions.insert(state["next"][0]["words"].get<std::string>());
  }
  std::printf("coverage after each located shot: ");
  for (double p : percents) std::printf("%.1f%% ", p);
  std::printf("\n%zu distinct suggestions; slowest shot on the page %.2f s after the button\n", suggestions.size(), slowest_shot_s);
  EXPECT_LT(slowest_shot_s, 2.0);  // a 1200x800 render and its download included
  ASSERT_GE(percents.size(), 5u);
  EXPECT_GT(percents.back(), percents.front() + 10);
  EXPECT_GE(suggestions.size(), 3u);
  Json state = State(port);
  int usable = 0;
  for (const Json& shot : state["shots"]) usable += shot["usable"] == true;
  EXPECT_GE(usable, 6) << state.dump();
  for (const Json& shot : state["shots"])
    if (shot["usable"] == false) {
      EXPECT_FALSE(shot["why_not"].empty()) << shot.dump();  // each refusal says why
    }

  // Undo: the last shot is rejected in the journal, its file stays.
  ASSERT_EQ(Post(port, "/api/undo"), 202);
  state = WaitFor(port, [](const Json& s) { return s["shots"].back()["rejected"] == true; });
  ASSERT_FALSE(state.is_null());
  const std::string undone = state["shots"].back()["file"];
  EXPECT_TRUE(fs::exists(session / undone));
  std::ifstream journal(SessionLayout(session).journal());
  std::string line, last;
  while (std::getline(journal, line)) last = line;
  EXPECT_EQ(Json::parse(last)["event"], "reject");

  // Finish: process runs under the console's lock and the page gets the report's link.
  ASSERT_EQ(Post(port, "/api/finish"), 202);
  EXPECT_EQ(Post(port, "/api/shot"), 409);
  state = WaitFor(port, [](const Json& s) { return s["process"]["state"] != "idle" && s["process"]["state"] != "running"; }, 600);
  ASSERT_FALSE(state.is_null());
  ASSERT_EQ(state["process"]["state"], "done") << state["process"].dump();
  EXPECT_FALSE(state["process"]["lines"].empty());
  const std::string report = state["process"]["report"];
  const testing::RawReply page = testing::LocalRequest(port, "GET " + report);
  EXPECT_EQ(page.status, 200);
  EXPECT_NE(page.text.find("<html"), std::string::npos);
  ::kill(console.pid, SIGTERM);
  EXPECT_EQ(WaitForExit(console.pid, 60), 0);
  // Every stage left the undone shot out.
  std::ifstream calibration(SessionLayout(session).calibration().report());
  const std::string calibration_text((std::istreambuf_iterator<char>(calibration)), {});
  EXPECT_NE(calibration_text.find("shots/shot_0011.jpg"), std::string::npos);
  EXPECT_EQ(calibration_text.find(undone), std::string::npos);

  // Each of the 20 streams saw every shot arrive, the undo and the end.
  for (size_t w = 0; w < watchers.size(); ++w) {
    std::set<std::string> shots;
    bool saw_undo = false, saw_finish = false;
    for (const Json& e : watchers[w]->events()) {
      if (e["type"] == "shot") shots.insert(e["file"].get<std::string>());
      saw_undo |= e["type"] == "undo";
      saw_finish |= e["type"] == "finished";
    }
    EXPECT_EQ(shots.size(), 22u) << "stream " << w;
    EXPECT_TRUE(saw_undo && saw_finish) << "stream " << w;
  }
}

// The page itself in headless Chromium, driven over the DevTools protocol
// (scripts/console_browser.py): its scripted operator (#operator=30) presses the buttons as a
// person following it would. Every shot shows within 2 s of its arrival, the coverage rises, the
// suggestion changes, undo and finish work, the report's link answers, and no script error or
// console.error happens.
TEST(Console, ThePageInHeadlessChromiumFollowsAThirtyShotSession) {
  const fs::path dir = testing::MakeTempDir(), session = dir / "s";
  RunningConsole console = StartConsole(session.string() + " " + kCamera +
                                            " --follow-guide --guide-after 5 --process-args "
                                            "'--slice-size 64 --btf-size 32 --btf-grid coarse'",
                                        dir / "console.log");
  ASSERT_GT(console.port, 0);
  std::string out;
  const char* source = std::getenv("MESOCAP_SOURCE_DIR");
  ASSERT_NE(source, nullptr) << "run through ctest (MESOCAP_SOURCE_DIR)";
  const std::string driver = std::string(source) + "/scripts/console_browser.py";
  const int code = testing::RunCommand("/usr/bin/python3 " + driver + " http://127.0.0.1:" + std::to_string(console.port) +
                                           "/ --operator 30 --calibration 10 --timeout 600 2>&1",
                                       &out);
  ::kill(console.pid, SIGTERM);
  EXPECT_EQ(WaitForExit(console.pid, 60), 0);
  ASSERT_EQ(code, 0) << out;
  const Json result = Json::parse(out.substr(out.rfind("\n{") == std::string::npos ? 0 : out.rfind("\n{") + 1), nullptr, false);
  ASSERT_FALSE(result.is_discarded()) << out;
  EXPECT_EQ(result["errors"], Json::array()) << out;
  EXPECT_EQ(result["page_errors"], "0") << out;
  const Json& op = result["operator"];
  ASSERT_TRUE(op.is_object()) << out;
  ASSERT_FALSE(op.contains("error")) << out;
  EXPECT_EQ(op["shots"], 30);
  ASSERT_EQ(op["shown_s"].size(), 40u) << out;  // the checkerboard shots too
  for (const Json& seconds : op["shown_s"]) EXPECT_LT(seconds.get<double>(), 2.0) << out;
  ASSERT_GE(op["percents"].size(), 20u);
  EXPECT_GT(op["percents"].back().get<double>(), op["percents"].front().get<double>() + 30) << out;
  EXPECT_GE(op["suggestions"].get<int>(), 5);
  EXPECT_GE(op["plots"].get<int>(), 20);  // the boards' hemispheres redrawn after the shots
  EXPECT_EQ(op["undone"], Json::array({"shots/shot_0030.jpg"}));
  EXPECT_EQ(op["process"], "done");
  EXPECT_EQ(op["report_status"], 200);
  std::printf("in Chromium: 30 shots, coverage %.1f%% -> %.1f%%, %d distinct suggestions\n",
              op["percents"].front().get<double>(), op["percents"].back().get<double>(), op["suggestions"].get<int>());
}

TEST(Console, AKilledConsoleResumesWithEveryShotOnce) {
  const fs::path dir = testing::MakeTempDir(), session = dir / "s";
  RunningConsole console = StartConsole(session.string() + " " + kCamera, dir / "first.log");
  ASSERT_GT(console.port, 0);
  for (size_t i = 1; i <= 6; ++i) {
    ASSERT_EQ(Post(console.port, "/api/shot"), 202);
    ASSERT_FALSE(WaitFor(console.port, [&](const Json& s) { return Count(s, "shot", false) == i; }).is_null());
  }
  ASSERT_EQ(Post(console.port, "/api/shot"), 202);  // the seventh may be under way when the kill comes
  ::kill(console.pid, SIGKILL);
  ::waitpid(console.pid, nullptr, 0);

  RunningConsole again = StartConsole(session.string() + " --resume " + kCamera, dir / "second.log");
  ASSERT_GT(again.port, 0) << "see " << again.log;
  Json state = WaitFor(again.port, [](const Json& s) { return s["shots"].size() >= 6 && Count(s, "shot", true) == s["shots"].size(); });
  ASSERT_FALSE(state.is_null()) << State(again.port).dump();  // the page shows the earlier shots, read again
  const size_t before = state["shots"].size();
  ASSERT_EQ(Post(again.port, "/api/shot"), 202);
  state = WaitFor(again.port, [&](const Json& s) { return s["shots"].size() == before + 1; });
  ASSERT_FALSE(state.is_null());
  std::set<std::string> files;
  for (const Json& shot : state["shots"]) EXPECT_TRUE(files.insert(shot["file"].get<std::string>()).second) << shot.dump();
  EXPECT_EQ(state["shots"].back()["index"], int(before) + 1);
  ::kill(again.pid, SIGTERM);
  EXPECT_EQ(WaitForExit(again.pid, 30), 0);

  // Review: the same page, nothing captured or changed.
  RunningConsole review = StartConsole(session.string() + " --review", dir / "review.log");
  ASSERT_GT(review.port, 0);
  state = State(review.port);
  EXPECT_EQ(state["mode"], "review");
  EXPECT_EQ(state["shots"].size(), before + 1);
  for (const Json& shot : state["shots"]) {
    EXPECT_TRUE(shot["analysed"].get<bool>());  // shown as it is: not "reading"
    EXPECT_TRUE(shot["usable"].is_null());      // no calibration yet: not known
  }
  EXPECT_EQ(Post(review.port, "/api/shot"), 409);
  EXPECT_EQ(Post(review.port, "/api/undo"), 409);
  const testing::RawReply page = testing::LocalRequest(review.port, "GET /");
  EXPECT_EQ(page.status, 200);
  EXPECT_NE(page.text.find("EventSource"), std::string::npos);
  ::kill(review.pid, SIGINT);
  EXPECT_EQ(WaitForExit(review.pid, 30), 0);
}

}  // namespace
}  // namespace mesocap

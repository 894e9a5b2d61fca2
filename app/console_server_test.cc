// The capture console's web server against the security list of docs/console.md, with raw HTTP
// requests: wrong Host, wrong Origin, missing or wrong token, ".." and encoded ".." paths, a
// symlink out of the session, oversized and malformed requests, 200 slow clients at once. Each is
// refused, no action runs, nothing in the session changes, and the real client is still served.
#include "app/console_server.h"

#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <thread>

#include "app/console_state.h"
#include "tests/raw_http.h"
#include "tests/testing.h"

namespace mesocap::app {
namespace {

namespace fs = std::filesystem;

using testing::ConnectLocal;
using Reply = testing::RawReply;
Reply Raw(int port, const std::string& request) { return testing::RawRequest(port, request); }

class ConsoleServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::MakeTempDir();
    session_ = dir_ / "session";
    fs::create_directories(session_ / "shots");
    std::ofstream(session_ / "shots" / "shot_0001.jpg") << "jpeg bytes";
    std::ofstream(dir_ / "secret.txt") << "SECRET-CONTENT";
    fs::create_symlink(dir_ / "secret.txt", session_ / "shots" / "link_out.jpg");
    fs::create_directory_symlink(dir_, session_ / "folder_out");
    ConsoleServerOptions options;
    options.port = 0;
    options.token = "s3cret-token";
    options.session = session_;
    ConsoleActions actions;
    actions.shot = [this] { ++shots_; return std::string(); };
    actions.undo = [this] { ++undos_; return std::string("no flash shot to undo"); };
    auto started = ConsoleServer::Start(options, &state_, actions, "<html>mesocap console page</html>");
    ASSERT_TRUE(started.ok()) << started.status().message();
    server_ = std::move(*started);
    port_ = server_->port();
    host_ = "Host: 127.0.0.1:" + std::to_string(port_) + "\r\n";
  }
  void TearDown() override {
    state_.Close();
    if (server_) server_->Stop();
  }
  // A request with this console's Host and `headers`, closing the connection after the reply.
  Reply Request(const std::string& method_and_path, const std::string& headers = "", const std::string& body = "") {
    return Raw(port_, method_and_path + " HTTP/1.1\r\n" + host_ + headers + "Connection: close\r\nContent-Length: " +
                          std::to_string(body.size()) + "\r\n\r\n" + body);
  }
  std::vector<std::string> SessionFiles() const {
    std::vector<std::string> files;
    for (const auto& entry : fs::recursive_directory_iterator(session_)) files.push_back(entry.path().string());
    std::sort(files.begin(), files.end());
    return files;
  }

  fs::path dir_, session_;
  ConsoleState state_{Json{{"shots", Json::array()}}};
  std::unique_ptr<ConsoleServer> server_;
  int port_ = 0;
  std::string host_;
  std::atomic<int> shots_{0}, undos_{0};
  const std::string bearer_ = "Authorization: Bearer s3cret-token\r\n";
};

TEST(ConsoleRules, HostsTokensAndFileNames) {
  EXPECT_TRUE(IsLoopbackHost("127.0.0.1"));
  EXPECT_TRUE(IsLoopbackHost("localhost"));
  EXPECT_FALSE(IsLoopbackHost("0.0.0.0"));
  EXPECT_FALSE(IsLoopbackHost("192.168.1.7"));
  EXPECT_TRUE(IsLoopbackHost("127.3.4.5"));
  EXPECT_FALSE(IsLoopbackHost("127.evil.example"));
  EXPECT_TRUE(IsValidToken("s3cret-token_1.0"));
  EXPECT_FALSE(IsValidToken("short"));
  EXPECT_FALSE(IsValidToken("with space or ;"));
  const std::vector<std::string> own = OwnHostNames("127.0.0.1", 8765);
  for (const char* name : {"127.0.0.1:8765", "localhost:8765", "[::1]:8765"})
    EXPECT_NE(std::find(own.begin(), own.end(), name), own.end()) << name;
  for (const char* name : {"127.0.0.1", "evil.example:8765", "127.0.0.1:8766"})
    EXPECT_EQ(std::find(own.begin(), own.end(), name), own.end()) << name;
  EXPECT_EQ(OwnHostNames("192.168.1.7", 80), std::vector<std::string>{"192.168.1.7:80"});
  EXPECT_EQ(RequestToken("Bearer abc", "", "mesocap_console_80"), "abc");
  EXPECT_EQ(RequestToken("", "theme=dark; mesocap_console_80=xyz; other=1", "mesocap_console_80"), "xyz");
  EXPECT_EQ(RequestToken("Basic abc", "mesocap_console_81=1", "mesocap_console_80"), "");
  EXPECT_TRUE(SameToken("abc", "abc"));
  EXPECT_FALSE(SameToken("abc", "abd"));
  EXPECT_FALSE(SameToken("abc", "abcd"));
  EXPECT_EQ(RandomToken().size(), 32u);
  EXPECT_NE(RandomToken(), RandomToken());
}

TEST_F(ConsoleServerTest, FilesComeOnlyFromInsideTheSession) {
  auto ok = SessionFileFor(session_, "shots/shot_0001.jpg");
  ASSERT_TRUE(ok.ok()) << ok.status().message();
  for (const char* bad : {"..", "../secret.txt", "shots/../../secret.txt", "/etc/passwd", "shots//shot_0001.jpg",
                          "shots/./shot_0001.jpg", "%2e%2e/secret.txt", "shots\\..\\x", "shots/link_out.jpg",
                          "folder_out/secret.txt", "shots/missing.jpg", "shots"})
    EXPECT_FALSE(SessionFileFor(session_, bad).ok()) << bad;
  // The same through the server: the file itself, then each way out refused.
  Reply reply = Request("GET /files/shots/shot_0001.jpg", bearer_);
  EXPECT_EQ(reply.status, 200) << reply.text;
  EXPECT_NE(reply.text.find("jpeg bytes"), std::string::npos);
  for (const char* path : {"/files/../secret.txt", "/files/%2e%2e/secret.txt", "/files/shots/%2e%2e/%2e%2e/secret.txt",
                           "/files/%2E%2E%2Fsecret.txt", "/files/shots/link_out.jpg", "/files/folder_out/secret.txt",
                           "/files/shots/shot_0001.jpg%00.html", "/../secret.txt"}) {
    reply = Request(std::string("GET ") + path, bearer_);
    EXPECT_GE(reply.status, 400) << path;
    EXPECT_LT(reply.status, 500) << path;
    EXPECT_EQ(reply.text.find("SECRET-CONTENT"), std::string::npos) << path;
  }
}

TEST_F(ConsoleServerTest, TheTokenHostAndOriginAreChecked) {
  EXPECT_EQ(Request("GET /").status, 401);
  EXPECT_EQ(Request("GET /api/state", "Authorization: Bearer wrong\r\n").status, 401);
  EXPECT_EQ(Request("GET /?token=wrong").status, 401);
  EXPECT_EQ(Request("GET /api/state", bearer_).status, 200);
  EXPECT_EQ(Request("GET /api/state", "Cookie: mesocap_console_" + std::to_string(port_) + "=s3cret-token\r\n").status, 200);
  EXPECT_EQ(Request("GET /api/state", "Cookie: mesocap_console_1=s3cret-token\r\n").status, 401);  // another console's
  // The page's first load with ?token= sets the cookie its own requests then carry.
  const Reply first = Request("GET /?token=s3cret-token");
  EXPECT_EQ(first.status, 303);
  EXPECT_NE(first.text.find("Set-Cookie: mesocap_console_" + std::to_string(port_) + "=s3cret-token; HttpOnly; SameSite=Strict"),
            std::string::npos) << first.text;
  // DNS rebinding and cross-site requests.
  Reply wrong_host = Raw(port_, "GET /api/state HTTP/1.1\r\nHost: evil.example:" + std::to_string(port_) + "\r\n" + bearer_ +
                                    "Connection: close\r\n\r\n");
  EXPECT_EQ(wrong_host.status, 403);
  EXPECT_EQ(Raw(port_, "GET /api/state HTTP/1.1\r\n" + bearer_ + "Connection: close\r\n\r\n").status, 403);  // no Host
  EXPECT_EQ(Request("GET /api/state", bearer_ + "Origin: http://evil.example\r\n").status, 403);
  EXPECT_EQ(Request("POST /api/shot", bearer_ + "Origin: http://evil.example\r\n").status, 403);
  EXPECT_EQ(Request("POST /api/shot", "Origin: http://127.0.0.1:" + std::to_string(port_) + "\r\n").status, 401);
  EXPECT_EQ(shots_, 0);
  EXPECT_EQ(Request("GET /api/state", bearer_ + "Origin: http://127.0.0.1:" + std::to_string(port_) + "\r\n").status, 200);
  // Changes are POSTs with the token; a refused action says why.
  EXPECT_EQ(Request("GET /api/shot", bearer_).status, 405);
  EXPECT_EQ(shots_, 0);
  EXPECT_EQ(Request("POST /api/shot", bearer_).status, 202);
  EXPECT_EQ(shots_, 1);
  const Reply undo = Request("POST /api/undo", bearer_);
  EXPECT_EQ(undo.status, 409);
  EXPECT_NE(undo.text.find("no flash shot to undo"), std::string::npos);
  EXPECT_EQ(Request("POST /api/finish", bearer_).status, 409);  // none given to this server
}

TEST_F(ConsoleServerTest, OversizedMalformedAndSlowRequestsAreRefusedAndTheRealClientIsServed) {
  const std::vector<std::string> before = SessionFiles();
  EXPECT_EQ(Request("GET /" + std::string(20000, 'a'), bearer_).status, 414);
  EXPECT_EQ(Request("GET /api/state", bearer_ + "X-Long: " + std::string(10000, 'b') + "\r\n").status, 400);
  EXPECT_EQ(Request("POST /api/shot", bearer_, std::string(100000, 'c')).status, 413);
  EXPECT_EQ(Raw(port_, "GARBAGE\r\n\r\n").status, 400);
  EXPECT_EQ(Raw(port_, "GET / HTTP/9.9\r\n" + host_ + "\r\n").status, 400);
  EXPECT_EQ(Request("PUT /api/shot", bearer_).status / 100, 4);
  EXPECT_EQ(Request("GET /api/state", "Authorization: Bearer s3cret-token%0d%0aX-Evil: 1\r\n").status, 401);
  EXPECT_EQ(Raw(port_, "GET / HTTP/1.1\r\nHost: %FF%FE\r\nConnection: close\r\n\r\n").status, 403);  // not UTF-8
  // 200 clients connect at once and send half a request each, never the rest.
  std::vector<int> slow;
  for (int i = 0; i < 200; ++i) {
    const int fd = ConnectLocal(port_);
    ASSERT_GE(fd, 0) << i;
    const std::string half = "GET /api/state HTTP/1.1\r\n" + host_;
    ::send(fd, half.data(), half.size(), MSG_NOSIGNAL);
    slow.push_back(fd);
  }
  const auto t0 = std::chrono::steady_clock::now();
  const Reply page = Request("GET /", bearer_);
  const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("the page, with 200 slow clients connected: %.2f s\n", waited);
  EXPECT_EQ(page.status, 200);
  EXPECT_NE(page.text.find("mesocap console page"), std::string::npos);
  EXPECT_LT(waited, 5.0);  // a thread each (256), and each slow client let go after the 1 s read time-out
  for (int fd : slow) ::close(fd);
  // A client that leaves an event stream midway costs nothing: the server goes on.
  const int stream = ConnectLocal(port_);
  const std::string events = "GET /api/events HTTP/1.1\r\n" + host_ + bearer_ + "\r\n";
  ::send(stream, events.data(), events.size(), MSG_NOSIGNAL);
  ::close(stream);
  EXPECT_EQ(Request("GET /api/state", bearer_).status, 200);
  EXPECT_EQ(shots_, 0);
  EXPECT_EQ(undos_, 0);
  EXPECT_EQ(SessionFiles(), before);
}

TEST(ConsoleState, EveryStreamGetsEveryEventInOrder) {
  ConsoleState state(Json{{"shots", Json::array()}});
  EXPECT_TRUE(state.EventsAfter(0, std::chrono::milliseconds(1)).empty());
  std::thread writer([&] {
    for (int i = 0; i < 50; ++i)
      state.Update([&](Json& s) { s["shots"].push_back(i); }, {{"type", "shot"}, {"n", i}});
  });
  int64_t seen = 0;
  std::vector<int> numbers;
  while (seen < 50)
    for (const ConsoleEvent& e : state.EventsAfter(seen, std::chrono::milliseconds(1000))) {
      EXPECT_EQ(e.id, seen + 1);
      seen = e.id;
      numbers.push_back(Json::parse(e.data)["n"].get<int>());
    }
  writer.join();
  for (int i = 0; i < 50; ++i) EXPECT_EQ(numbers[size_t(i)], i);
  EXPECT_EQ(state.Snapshot()["version"], 50);
  EXPECT_EQ(state.Snapshot()["shots"].size(), 50u);
  // A stream that fell behind the kept log is told to read the state anew.
  for (int i = 0; i < 5000; ++i) state.Update([](Json&) {}, {{"type", "note"}});
  const auto behind = state.EventsAfter(1, std::chrono::milliseconds(1));
  ASSERT_EQ(behind.size(), 1u);
  EXPECT_EQ(Json::parse(behind[0].data)["type"], "resync");
  // Close ends a waiting stream at once.
  std::thread closer([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    state.Close();
  });
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_TRUE(state.EventsAfter(state.version(), std::chrono::milliseconds(5000)).empty());
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(4));
  closer.join();
}

}  // namespace
}  // namespace mesocap::app

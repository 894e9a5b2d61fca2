// The capture console's web server (docs/console.md): the page, its API and the session's files,
// over cpp-httplib. It listens on 127.0.0.1 by default, where requests need no token; on any
// other address every request carries the token (a Bearer header, or the cookie the page's first
// load with ?token= sets). Every request's Host must be one of the console's own names and its
// Origin, when it has one, the console's own; files are served only from inside the session.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "app/console_state.h"
#include "core/status.h"

namespace mesocap::app {

struct ConsoleServerOptions {
  std::string host = "127.0.0.1";
  int port = 8765;                // 0: any free port
  std::string token;              // needed on every request when not empty
  std::filesystem::path session;  // /files/ serves from inside it
  int threads = 256;              // connections served at once (each event stream holds one)
};

// What the page's buttons do (POST /api/...). Each returns an error for the client (409), or
// empty once the request is accepted (queued: its effects arrive as events).
struct ConsoleActions {
  std::function<std::string()> shot, calibration_shot, undo, finish;
};

class ConsoleServer {
 public:
  static StatusOr<std::unique_ptr<ConsoleServer>> Start(const ConsoleServerOptions& options, ConsoleState* state,
                                                        ConsoleActions actions, std::string page);
  ~ConsoleServer();
  int port() const;
  // The page's address, with ?token= when one is needed.
  std::string url() const;
  void Stop();

 private:
  struct Impl;
  explicit ConsoleServer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// The rules, apart from the socket (tested one by one):
bool IsLoopbackHost(const std::string& host);  // localhost, ::1 or an address of 127.0.0.0/8
// Host header values the console answers to when listening on `host`:`port`: that address, the
// loopback names on loopback, this machine's name and addresses on a wildcard address.
std::vector<std::string> OwnHostNames(const std::string& host, int port);
// The token a request carries: its Bearer header, else its cookie `cookie_name`; empty when none.
std::string RequestToken(const std::string& authorization, const std::string& cookie, const std::string& cookie_name);
// A token a request can carry as is: 8 to 256 letters, digits, '.', '_' or '-' (header values
// reach the server percent-decoded).
bool IsValidToken(const std::string& token);
bool SameToken(const std::string& a, const std::string& b);  // in constant time
// The regular file `relative` (a request's path under /files/, decoded) names inside `session`;
// an error for "..", absolute or odd names, and for a file reached through a symlink out of it.
StatusOr<std::filesystem::path> SessionFileFor(const std::filesystem::path& session, const std::string& relative);
// A random token of 32 hex digits (/dev/urandom).
std::string RandomToken();

}  // namespace mesocap::app

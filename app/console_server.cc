#include "app/console_server.h"

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <netinet/in.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <fstream>
#include <map>
#include <set>
#include <thread>

#include <httplib.h>

#include "core/provenance.h"

namespace mesocap::app {
namespace fs = std::filesystem;

namespace {

constexpr const char* kTokenCookie = "mesocap_console";
constexpr size_t kMaxBody = 64 * 1024;  // the API's requests carry no body worth more

std::string ContentTypeOf(const fs::path& file) {
  static const std::map<std::string, std::string> types = {
      {".jpg", "image/jpeg"}, {".jpeg", "image/jpeg"}, {".png", "image/png"}, {".svg", "image/svg+xml"},
      {".html", "text/html; charset=utf-8"}, {".md", "text/markdown; charset=utf-8"}, {".txt", "text/plain; charset=utf-8"},
      {".log", "text/plain; charset=utf-8"}, {".json", "application/json"}, {".jsonl", "application/json"},
      {".css", "text/css"}, {".js", "text/javascript"}};
  const auto it = types.find(file.extension().string());
  return it == types.end() ? "application/octet-stream" : it->second;
}

void Reply(httplib::Response& res, int status, const Json& body) {
  res.status = status;
  res.set_header("Cache-Control", "no-store");
  res.set_content(body.dump(-1, ' ', false, Json::error_handler_t::replace), "application/json");
}

// One cookie per console (its port), so two consoles on a host keep their own tokens.
std::string TokenCookie(int port) { return std::string(kTokenCookie) + "_" + std::to_string(port); }

std::string WithPort(const std::string& host, int port) {
  return (host.find(':') != std::string::npos ? "[" + host + "]" : host) + ":" + std::to_string(port);
}

// This machine's own addresses (every interface), for a console listening on all of them.
std::vector<std::string> InterfaceAddresses() {
  std::vector<std::string> out;
  ifaddrs* list = nullptr;
  if (::getifaddrs(&list) != 0) return out;
  for (ifaddrs* a = list; a; a = a->ifa_next) {
    if (!a->ifa_addr) continue;
    char text[INET6_ADDRSTRLEN] = {};
    if (a->ifa_addr->sa_family == AF_INET)
      ::inet_ntop(AF_INET, &reinterpret_cast<sockaddr_in*>(a->ifa_addr)->sin_addr, text, sizeof text);
    else if (a->ifa_addr->sa_family == AF_INET6)
      ::inet_ntop(AF_INET6, &reinterpret_cast<sockaddr_in6*>(a->ifa_addr)->sin6_addr, text, sizeof text);
    if (text[0]) out.push_back(text);
  }
  ::freeifaddrs(list);
  return out;
}

}  // namespace

bool IsLoopbackHost(const std::string& host) {
  in_addr v4{};
  if (::inet_pton(AF_INET, host.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  return host == "localhost" || host == "::1";
}

bool IsValidToken(const std::string& token) {
  return token.size() >= 8 && token.size() <= 256 &&
         std::all_of(token.begin(), token.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-'; });
}

std::vector<std::string> OwnHostNames(const std::string& host, int port) {
  std::vector<std::string> names = {WithPort(host, port)};
  const bool wildcard = host.empty() || host == "0.0.0.0" || host == "::";
  if (IsLoopbackHost(host) || wildcard)
    for (const char* loopback : {"localhost", "127.0.0.1", "::1"}) names.push_back(WithPort(loopback, port));
  if (wildcard) {
    names.push_back(WithPort(HostName(), port));
    for (const std::string& address : InterfaceAddresses()) names.push_back(WithPort(address, port));
  }
  return names;
}

std::string RequestToken(const std::string& authorization, const std::string& cookie, const std::string& cookie_name) {
  const std::string bearer = "Bearer ";
  if (authorization.rfind(bearer, 0) == 0) return authorization.substr(bearer.size());
  size_t start = 0;
  while (start < cookie.size()) {
    size_t end = cookie.find(';', start);
    if (end == std::string::npos) end = cookie.size();
    std::string pair = cookie.substr(start, end - start);
    pair.erase(0, pair.find_first_not_of(' '));
    const size_t eq = pair.find('=');
    if (eq != std::string::npos && pair.substr(0, eq) == cookie_name) return pair.substr(eq + 1);
    start = end + 1;
  }
  return "";
}

bool SameToken(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  unsigned char differ = 0;
  for (size_t i = 0; i < a.size(); ++i) differ |= static_cast<unsigned char>(a[i] ^ b[i]);
  return differ == 0;
}

StatusOr<fs::path> SessionFileFor(const fs::path& session, const std::string& relative) {
  const auto refused = [&](const std::string& why) { return Status::Error("/files/" + relative + ": " + why); };
  if (relative.empty() || relative.size() > 1024 || relative.find_first_of(std::string("\\%\0", 3)) != std::string::npos)
    return refused("not a file name of the session");
  size_t start = 0;
  while (start <= relative.size()) {
    const size_t end = std::min(relative.find('/', start), relative.size());
    const std::string part = relative.substr(start, end - start);
    if (part.empty() || part == "." || part == "..") return refused("not a file name of the session");
    start = end + 1;
  }
  std::error_code ec;
  const fs::path root = fs::canonical(session, ec);
  if (ec) return refused("the session cannot be read");
  const fs::path real = fs::canonical(root / relative, ec);
  if (ec || !fs::is_regular_file(real, ec)) return refused("no such file");
  const auto [root_end, _] = std::mismatch(root.begin(), root.end(), real.begin(), real.end());
  if (root_end != root.end()) return refused("outside the session");  // a symlink out of it
  return real;
}

std::string RandomToken() {
  unsigned char bytes[16] = {};
  std::ifstream random("/dev/urandom", std::ios::binary);
  random.read(reinterpret_cast<char*>(bytes), sizeof bytes);
  static const char* hex = "0123456789abcdef";
  std::string token;
  for (unsigned char b : bytes) token += {hex[b >> 4], hex[b & 15]};
  return token;
}

struct ConsoleServer::Impl {
  ConsoleServerOptions options;
  ConsoleState* state = nullptr;
  ConsoleActions actions;
  std::string page;
  httplib::Server server;
  std::thread listener;
  int port = 0;
  std::set<std::string> hosts, origins;
  std::atomic<bool> stopping{false};

  httplib::Server::HandlerResponse Screen(const httplib::Request& req, httplib::Response& res);
  void Routes();
  void Action(const char* path, std::function<std::string()> ConsoleActions::*action);
};

// Every request, before its route: its Host and Origin must be the console's own, and it must
// carry the token when one is set (the page's first load may bring it as ?token= for a cookie).
httplib::Server::HandlerResponse ConsoleServer::Impl::Screen(const httplib::Request& req, httplib::Response& res) {
  using R = httplib::Server::HandlerResponse;
  if (!hosts.count(req.get_header_value("Host"))) {
    Reply(res, 403, {{"error", "this console does not answer to Host '" + req.get_header_value("Host") + "'"}});
    return R::Handled;
  }
  if (req.has_header("Origin") && !origins.count(req.get_header_value("Origin"))) {
    Reply(res, 403, {{"error", "cross-origin requests are refused"}});
    return R::Handled;
  }
  if (options.token.empty()) return R::Unhandled;
  if (req.method == "GET" && req.path == "/" && req.has_param("token") && SameToken(req.get_param_value("token"), options.token)) {
    res.set_header("Set-Cookie", TokenCookie(port) + "=" + options.token + "; HttpOnly; SameSite=Strict; Path=/");
    res.set_redirect("/", 303);
    return R::Handled;
  }
  if (!SameToken(RequestToken(req.get_header_value("Authorization"), req.get_header_value("Cookie"), TokenCookie(port)),
                 options.token)) {
    res.set_header("WWW-Authenticate", "Bearer");
    Reply(res, 401, {{"error", "this console needs its token (the address it printed, or Authorization: Bearer TOKEN)"}});
    return R::Handled;
  }
  return R::Unhandled;
}

void ConsoleServer::Impl::Action(const char* path, std::function<std::string()> ConsoleActions::*action) {
  server.Post(path, [this, action](const httplib::Request&, httplib::Response& res) {
    const std::function<std::string()>& act = actions.*action;
    const std::string refused = act ? act() : "not available in this console";
    if (refused.empty()) Reply(res, 202, {{"queued", true}});
    else Reply(res, 409, {{"error", refused}});
  });
  server.Get(path, [](const httplib::Request&, httplib::Response& res) {
    res.set_header("Allow", "POST");
    Reply(res, 405, {{"error", "changes are POST requests"}});
  });
}

void ConsoleServer::Impl::Routes() {
  server.Get("/", [this](const httplib::Request&, httplib::Response& res) {
    res.set_header("Cache-Control", "no-store");
    res.set_header("X-Frame-Options", "DENY");
    res.set_header("X-Content-Type-Options", "nosniff");
    res.set_header("Content-Security-Policy",
                   "default-src 'self'; img-src 'self' data:; style-src 'unsafe-inline'; script-src 'unsafe-inline'; "
                   "connect-src 'self'; frame-ancestors 'none'");
    res.set_content(page, "text/html; charset=utf-8");
  });
  server.Get("/api/state", [this](const httplib::Request&, httplib::Response& res) { Reply(res, 200, state->Snapshot()); });
  server.Get("/api/events", [this](const httplib::Request& req, httplib::Response& res) {
    auto last = std::make_shared<int64_t>(state->version());
    if (req.has_header("Last-Event-ID")) {  // a reconnecting stream picks up where it left off
      try {
        *last = std::min<int64_t>(std::stoll(req.get_header_value("Last-Event-ID")), *last);
      } catch (const std::exception&) {
      }
    }
    res.set_header("Cache-Control", "no-store");
    res.set_chunked_content_provider("text/event-stream", [this, last](size_t, httplib::DataSink& sink) {
      if (stopping || state->closed()) {
        sink.done();
        return true;
      }
      std::string text;
      for (const ConsoleEvent& e : state->EventsAfter(*last, std::chrono::milliseconds(1000))) {
        text += "id: " + std::to_string(e.id) + "\ndata: " + e.data + "\n\n";
        *last = e.id;
      }
      if (text.empty()) text = ": waiting\n\n";  // a client gone is noticed within a second
      return sink.write(text.data(), text.size());
    });
  });
  server.Get(R"(/files/(.+))", [this](const httplib::Request& req, httplib::Response& res) {
    auto file = SessionFileFor(options.session, req.matches[1]);
    if (!file.ok()) {
      const bool missing = file.status().message().find("no such file") != std::string::npos;
      return Reply(res, missing ? 404 : 403, {{"error", file.status().message()}});
    }
    auto in = std::make_shared<std::ifstream>(*file, std::ios::binary | std::ios::ate);
    if (!*in) return Reply(res, 404, {{"error", "/files/" + std::string(req.matches[1]) + ": cannot be read"}});
    const size_t size = size_t(in->tellg());  // of the file opened (one renamed over it meanwhile is not mixed in)
    res.set_header("Cache-Control", "no-cache");
    res.set_content_provider(size, ContentTypeOf(*file), [in](size_t offset, size_t length, httplib::DataSink& sink) {
      std::vector<char> buffer(std::min<size_t>(length, 1 << 16));
      in->seekg(std::streamoff(offset));
      in->read(buffer.data(), std::streamsize(buffer.size()));
      return in->gcount() > 0 && sink.write(buffer.data(), size_t(in->gcount()));
    });
  });
  Action("/api/shot", &ConsoleActions::shot);
  Action("/api/calibration-shot", &ConsoleActions::calibration_shot);
  Action("/api/undo", &ConsoleActions::undo);
  Action("/api/finish", &ConsoleActions::finish);
  server.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) { return Screen(req, res); });
  server.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
    Reply(res, 500, {{"error", "internal error"}});
  });
  server.set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (res.body.empty()) Reply(res, res.status, {{"error", res.status == 404 ? "no such page" : "bad request"}});
  });
}

ConsoleServer::ConsoleServer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
ConsoleServer::~ConsoleServer() { Stop(); }

StatusOr<std::unique_ptr<ConsoleServer>> ConsoleServer::Start(const ConsoleServerOptions& options, ConsoleState* state,
                                                              ConsoleActions actions, std::string page) {
  if (!IsLoopbackHost(options.host) && options.token.empty())
    return Status::Error("listening on " + options.host + " needs a token (--token, or let the console make one)");
  if (!options.token.empty() && !IsValidToken(options.token))
    return Status::Error("the token must be 8 to 256 letters, digits, '.', '_' or '-'");
  auto impl = std::make_unique<Impl>();
  impl->options = options;
  impl->state = state;
  impl->actions = std::move(actions);
  impl->page = std::move(page);
  const int threads = std::max(4, options.threads);
  impl->server.new_task_queue = [threads] { return new httplib::ThreadPool(size_t(threads)); };
  // Slow or silent clients let go of their thread soon; event streams write every second.
  impl->server.set_read_timeout(1, 0);
  impl->server.set_write_timeout(5, 0);
  impl->server.set_keep_alive_timeout(2);
  impl->server.set_payload_max_length(kMaxBody);
  impl->Routes();
  const bool bound = options.port == 0 ? (impl->port = impl->server.bind_to_any_port(options.host)) > 0
                                       : impl->server.bind_to_port(options.host, impl->port = options.port);
  if (!bound) return Status::Error("cannot listen on " + WithPort(options.host, options.port) + " (in use, or not this machine's address)");
  for (const std::string& name : OwnHostNames(options.host, impl->port)) {
    impl->hosts.insert(name);
    impl->origins.insert("http://" + name);
  }
  Impl* raw = impl.get();
  impl->listener = std::thread([raw] { raw->server.listen_after_bind(); });
  // httplib's stop() does nothing until the loop runs: a Stop right after Start would wait forever.
  for (int i = 0; i < 500 && !impl->server.is_running(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  return std::unique_ptr<ConsoleServer>(new ConsoleServer(std::move(impl)));
}

int ConsoleServer::port() const { return impl_->port; }

std::string ConsoleServer::url() const {
  return "http://" + WithPort(impl_->options.host, impl_->port) + "/" +
         (impl_->options.token.empty() ? "" : "?token=" + impl_->options.token);
}

void ConsoleServer::Stop() {
  if (!impl_ || !impl_->listener.joinable()) return;
  impl_->stopping = true;
  impl_->server.stop();
  impl_->listener.join();
}

}  // namespace mesocap::app

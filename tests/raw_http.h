// Raw HTTP over a socket for tests of the capture console: requests sent byte for byte (malformed
// ones too) and Server-Sent Events read as they come.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <cstdlib>
#include <string>

namespace mesocap::testing {

// A connection to 127.0.0.1:`port` whose reads give up after `timeout_s`; -1 when refused.
inline int ConnectLocal(int port, int timeout_s = 10) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(uint16_t(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
    ::close(fd);
    return -1;
  }
  timeval timeout{timeout_s, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  return fd;
}

struct RawReply {
  int status = 0;    // 0: no reply
  std::string text;  // head and body
  std::string body() const {
    const size_t end = text.find("\r\n\r\n");
    return end == std::string::npos ? "" : text.substr(end + 4);
  }
};

// Sends `request` as is and reads the reply until the server closes (send Connection: close).
inline RawReply RawRequest(int port, const std::string& request) {
  RawReply reply;
  const int fd = ConnectLocal(port);
  if (fd < 0) return reply;
  ::send(fd, request.data(), request.size(), MSG_NOSIGNAL);
  char buffer[65536];
  for (ssize_t n; (n = ::recv(fd, buffer, sizeof buffer, 0)) > 0;) reply.text.append(buffer, size_t(n));
  ::close(fd);
  if (reply.text.rfind("HTTP/1.1 ", 0) == 0) reply.status = std::atoi(reply.text.c_str() + 9);
  return reply;
}

// A well-formed request to the console on loopback: METHOD PATH, extra header lines, a body.
inline RawReply LocalRequest(int port, const std::string& method_and_path, const std::string& headers = "",
                             const std::string& body = "") {
  return RawRequest(port, method_and_path + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) + "\r\n" + headers +
                              "Connection: close\r\nContent-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body);
}

}  // namespace mesocap::testing

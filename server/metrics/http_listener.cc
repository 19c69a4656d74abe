#include "server/metrics/http_listener.h"

#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "server/metrics/text_format.h"

namespace mbstream::metrics {

namespace {

constexpr size_t kMaxRequestBytes = 8192;
constexpr int kTimeoutS = 2;  // per read and write of one connection

std::runtime_error ListenError(const std::string& address, const std::string& why) {
  return std::runtime_error("cannot serve metrics on " + address + ": " + why +
                            " (give --metrics host:port with a local address and a free port, "
                            "or port 0 for any)");
}

void SendAll(int fd, const std::string& data) {
  size_t sent = 0;
  while (sent < data.size()) {
    const ssize_t n = send(fd, data.data() + sent, data.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) return;  // the scraper went away or timed out: nothing to tell it
    sent += static_cast<size_t>(n);
  }
}

std::string Response(const std::string& status, const std::string& content_type,
                     const std::string& body, const std::string& extra_headers = "") {
  return "HTTP/1.1 " + status + "\r\nContent-Type: " + content_type +
         "\r\nContent-Length: " + std::to_string(body.size()) + "\r\n" + extra_headers +
         "Connection: close\r\n\r\n" + body;
}

}  // namespace

std::unique_ptr<HttpListener> HttpListener::Start(const std::string& host_port,
                                                  std::function<std::string()> render) {
  const size_t colon = host_port.rfind(':');
  if (colon == std::string::npos || colon + 1 == host_port.size()) {
    throw ListenError(host_port, "expected host:port");
  }
  std::string host = host_port.substr(0, colon);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') {
    host = host.substr(1, host.size() - 2);
  }
  const std::string port = host_port.substr(colon + 1);
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  addrinfo* found = nullptr;
  if (const int error =
          getaddrinfo(host.empty() ? nullptr : host.c_str(), port.c_str(), &hints, &found);
      error != 0) {
    throw ListenError(host_port, gai_strerror(error));
  }
  std::unique_ptr<HttpListener> listener(new HttpListener());
  int fd = socket(found->ai_family, found->ai_socktype | SOCK_CLOEXEC, found->ai_protocol);
  const int on = 1;
  if (fd >= 0) setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);
  if (fd < 0 || bind(fd, found->ai_addr, found->ai_addrlen) != 0 || listen(fd, 16) != 0) {
    const std::string why = std::strerror(errno);
    if (fd >= 0) close(fd);
    freeaddrinfo(found);
    throw ListenError(host_port, why);
  }
  freeaddrinfo(found);
  listener->listen_fd_ = fd;
  sockaddr_storage bound{};
  socklen_t length = sizeof bound;
  getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &length);
  const int bound_port =
      ntohs(bound.ss_family == AF_INET6 ? reinterpret_cast<sockaddr_in6*>(&bound)->sin6_port
                                        : reinterpret_cast<sockaddr_in*>(&bound)->sin_port);
  listener->address_ = host_port.substr(0, colon) + ":" + std::to_string(bound_port);
  if (pipe2(listener->wake_fds_, O_CLOEXEC) != 0) {
    throw ListenError(host_port, std::string("pipe: ") + std::strerror(errno));
  }
  listener->render_ = std::move(render);
  listener->thread_ = std::thread([raw = listener.get()] { raw->Serve(); });
  return listener;
}

HttpListener::~HttpListener() {
  if (wake_fds_[1] >= 0) {
    const char byte = 0;
    [[maybe_unused]] const ssize_t n = write(wake_fds_[1], &byte, 1);
  }
  if (thread_.joinable()) thread_.join();
  for (const int fd : {listen_fd_, wake_fds_[0], wake_fds_[1]}) {
    if (fd >= 0) close(fd);
  }
}

void HttpListener::Serve() {
  pollfd fds[2] = {{listen_fd_, POLLIN, 0}, {wake_fds_[0], POLLIN, 0}};
  while (true) {
    if (poll(fds, 2, -1) < 0) {
      if (errno == EINTR) continue;
      return;
    }
    if (fds[1].revents != 0) return;
    if ((fds[0].revents & POLLIN) == 0) continue;
    const int connection = accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
    if (connection < 0) continue;
    const timeval timeout{kTimeoutS, 0};
    setsockopt(connection, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
    setsockopt(connection, SOL_SOCKET, SO_SNDTIMEO, &timeout, sizeof timeout);
    Answer(connection);
    close(connection);
  }
}

void HttpListener::Answer(int connection) const {
  std::string request;
  char buffer[1024];
  while (request.find("\r\n\r\n") == std::string::npos && request.size() < kMaxRequestBytes) {
    const ssize_t n = recv(connection, buffer, sizeof buffer, 0);
    if (n <= 0) break;
    request.append(buffer, static_cast<size_t>(n));
  }
  const size_t line_end = request.find("\r\n");
  if (line_end == std::string::npos) {
    SendAll(connection, Response("400 Bad Request", "text/plain", "incomplete request\n"));
    return;
  }
  const std::string line = request.substr(0, line_end);  // "GET /metrics HTTP/1.1"
  const size_t space = line.find(' ');
  const std::string method = line.substr(0, space);
  const size_t target_end = line.find(' ', space + 1);
  std::string target =
      space == std::string::npos ? "" : line.substr(space + 1, target_end - space - 1);
  target = target.substr(0, target.find('?'));
  if (method != "GET") {
    SendAll(connection, Response("405 Method Not Allowed", "text/plain", "only GET /metrics\n",
                                 "Allow: GET\r\n"));
  } else if (target != "/metrics") {
    SendAll(connection, Response("404 Not Found", "text/plain", "metrics are at /metrics\n"));
  } else {
    SendAll(connection, Response("200 OK", kTextContentType, render_()));
  }
}

}  // namespace mbstream::metrics

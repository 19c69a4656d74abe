// A minimal HTTP/1.1 listener for Prometheus scrapes: GET /metrics answers with the text
// `render` returns (text_format.h), every other path 404, every other method 405; one
// request per connection (Connection: close).
//
// Written here because Debian 12 has neither libprometheus-cpp-dev nor a small embeddable HTTP
// server library in the dependencies we already use; a scrape is one short request every few
// seconds, so one thread serving one connection at a time (each bounded by a 2 s timeout
// and an 8 KiB request) is enough, and keeps the metrics port from competing with gRPC.
// Plain HTTP: give a loopback or private address, as for any Prometheus exporter.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <thread>

namespace mbstream::metrics {

class HttpListener {
 public:
  // Listens on `host:port` (port 0 = any free port; host a name or a numeric address) and
  // starts serving. Throws std::runtime_error naming the address and the reason when it
  // cannot.
  static std::unique_ptr<HttpListener> Start(const std::string& host_port,
                                             std::function<std::string()> render);
  ~HttpListener();  // stops serving and closes the socket
  HttpListener(const HttpListener&) = delete;
  HttpListener& operator=(const HttpListener&) = delete;

  // host:port with the port actually bound.
  const std::string& address() const { return address_; }

 private:
  HttpListener() = default;
  void Serve();
  void Answer(int connection) const;

  std::function<std::string()> render_;
  std::string address_;
  int listen_fd_ = -1;
  int wake_fds_[2] = {-1, -1};  // a pipe: writing to [1] ends Serve()
  std::thread thread_;
};

}  // namespace mbstream::metrics

// A private Xvfb for a test: it picks a free display number itself (-displayfd), so that two
// tests started together never collide. Started with -noreset, as scripts/with-xvfb.sh does.
#pragma once

#include <sys/types.h>

#include <string>

namespace mbstream::viewer::testing {

class XvfbServer {
 public:
  XvfbServer() = default;
  ~XvfbServer() { Stop(); }
  XvfbServer(const XvfbServer&) = delete;
  XvfbServer& operator=(const XvfbServer&) = delete;

  // Starts Xvfb and waits until it accepts clients; false when it cannot start.
  bool Start();
  // ":N" once started.
  const std::string& display() const { return display_; }
  pid_t pid() const { return pid_; }
  // Ends it (SIGTERM, or SIGKILL: the server dies without a word to its clients) and waits
  // until it has exited, so that its clients' connections are closed when this returns.
  void Stop();
  void Kill();

 private:
  void Signal(int signal);
  pid_t pid_ = -1;
  std::string display_;
};

}  // namespace mbstream::viewer::testing

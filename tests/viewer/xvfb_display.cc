#include "tests/viewer/xvfb_display.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <string>

namespace mbstream::viewer::testing {

namespace {

class XvfbEnvironment : public ::testing::Environment {
 public:
  void SetUp() override { EnsureDisplay(); }
  void TearDown() override { Stop(); }

  bool Start() {
    if (pid_ > 0) return true;
    int fds[2];
    if (pipe(fds) != 0) return false;
    const pid_t pid = fork();
    if (pid < 0) return false;
    if (pid == 0) {
      close(fds[0]);
      const std::string fd = std::to_string(fds[1]);
      execlp("Xvfb", "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "1280x1024x24", "-nolisten",
             "tcp", "-noreset", static_cast<char*>(nullptr));
      _exit(127);
    }
    close(fds[1]);
    std::string number;
    char c = 0;
    while (read(fds[0], &c, 1) == 1 && c != '\n') number += c;
    close(fds[0]);
    if (number.empty()) {
      kill(pid, SIGTERM);
      waitpid(pid, nullptr, 0);
      return false;
    }
    pid_ = pid;
    setenv("DISPLAY", (":" + number).c_str(), 1);
    return true;
  }

  void Stop() {
    if (pid_ <= 0) return;
    kill(pid_, SIGTERM);
    waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }

 private:
  pid_t pid_ = -1;
};

XvfbEnvironment* const environment =
    static_cast<XvfbEnvironment*>(::testing::AddGlobalTestEnvironment(new XvfbEnvironment));

}  // namespace

bool EnsureDisplay() {
  const char* display = std::getenv("DISPLAY");
  if (display && *display) return true;
  return environment->Start();
}

}  // namespace mbstream::viewer::testing

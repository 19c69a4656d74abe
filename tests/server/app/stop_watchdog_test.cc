// mbstream-server's stop watchdog (server/app/server_signals.h), each case in a child
// process: a second stop signal or the limit ends the process with status 1; a watchdog
// destroyed first ends nothing, and an interrupted wait (a handled signal) is not a stop.
#include <gmock/gmock.h>
#include <sched.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "server/app/server_signals.h"

namespace mbstream::testing {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

struct ChildEnd {
  int status;          // exit status, or 128 + the signal that ended it
  std::string output;  // stdout and stderr (the watchdog's log line)
};

// Runs `body` in a child and waits for its end.
ChildEnd InChild(const std::function<void()>& body) {
  int out[2];
  EXPECT_EQ(pipe(out), 0);
  const pid_t pid = fork();
  if (pid == 0) {
    close(out[0]);
    dup2(out[1], STDOUT_FILENO);
    dup2(out[1], STDERR_FILENO);
    body();
    _exit(0);
  }
  close(out[1]);
  ChildEnd end{0, ""};
  char buffer[256];
  for (ssize_t n; (n = read(out[0], buffer, sizeof buffer)) > 0;) end.output.append(buffer, n);
  close(out[0]);
  int status = 0;
  EXPECT_EQ(waitpid(pid, &status, 0), pid);
  end.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return end;
}

// Waits for signals forever: the child ends only through the watchdog.
[[noreturn]] void WaitForever() {
  for (;;) pause();
}

TEST(StopWatchdogTest, ASecondStopSignalEndsTheProcess) {
  const ChildEnd end = InChild([] {
    const sigset_t signals = BlockStopSignals();
    StopWatchdog watchdog;
    watchdog.Arm(signals, std::chrono::hours(1));
    kill(getpid(), SIGINT);
    WaitForever();
  });
  EXPECT_EQ(end.status, 1);
  EXPECT_THAT(end.output, HasSubstr("a second signal; exiting without waiting"));
}

TEST(StopWatchdogTest, ThePassedLimitEndsTheProcess) {
  const ChildEnd end = InChild([] {
    const sigset_t signals = BlockStopSignals();
    StopWatchdog watchdog;
    watchdog.Arm(signals, std::chrono::milliseconds(20));
    WaitForever();
  });
  EXPECT_EQ(end.status, 1);
  EXPECT_THAT(end.output, HasSubstr("the shutdown took over its limit"));
}

TEST(StopWatchdogTest, AWatchdogDestroyedBeforeItsLimitEndsNothing) {
  const ChildEnd end = InChild([] {
    const sigset_t signals = BlockStopSignals();
    { StopWatchdog unarmed; }
    {
      StopWatchdog watchdog;
      watchdog.Arm(signals, std::chrono::hours(1));
    }
    _exit(7);
  });
  EXPECT_EQ(end.status, 7);
  EXPECT_EQ(end.output, "");
}

// Returns once another thread of this process is blocked in sigtimedwait (the watchdog's
// wait), as the kernel reports it in /proc; yields in between.
void WaitUntilAThreadWaitsForSignals() {
  const std::string own = std::to_string(gettid());
  const std::string waiting = std::to_string(SYS_rt_sigtimedwait) + " ";
  for (;;) {
    for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
      if (task.path().filename() == own) continue;
      std::ifstream syscall(task.path() / "syscall");
      std::string line;
      std::getline(syscall, line);
      if (line.rfind(waiting, 0) == 0) return;
    }
    sched_yield();
  }
}

int handled_pipe[2];
void WriteHandled(int) {
  const char byte = 'h';
  [[maybe_unused]] const ssize_t written = write(handled_pipe[1], &byte, 1);
}

// A handled signal delivered to the watchdog's thread interrupts its wait (EINTR), as a
// debugger or the leak checker attaching does: that is not a stop, and the watchdog still
// answers the second stop signal that comes after it.
TEST(StopWatchdogTest, AnInterruptedWaitIsNotAStop) {
  const ChildEnd end = InChild([] {
    if (pipe(handled_pipe) != 0) _exit(20);
    struct sigaction action = {};
    action.sa_handler = WriteHandled;
    sigaction(SIGUSR1, &action, nullptr);
    const sigset_t signals = BlockStopSignals();
    StopWatchdog watchdog;
    watchdog.Arm(signals, std::chrono::hours(1));
    // Only the watchdog's thread (started before this) takes SIGUSR1 now.
    sigset_t usr1;
    sigemptyset(&usr1);
    sigaddset(&usr1, SIGUSR1);
    pthread_sigmask(SIG_BLOCK, &usr1, nullptr);
    WaitUntilAThreadWaitsForSignals();
    kill(getpid(), SIGUSR1);
    char byte = 0;
    if (read(handled_pipe[0], &byte, 1) != 1) _exit(21);
    kill(getpid(), SIGINT);
    WaitForever();
  });
  EXPECT_EQ(end.status, 1);
  EXPECT_THAT(end.output, HasSubstr("a second signal; exiting without waiting"));
  EXPECT_THAT(end.output, Not(HasSubstr("took over")));
}

}  // namespace
}  // namespace mbstream::testing

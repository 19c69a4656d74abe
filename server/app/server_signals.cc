#include "server/app/server_signals.h"

#include <spdlog/spdlog.h>

#include <cerrno>
#include <cstdlib>
#include <ctime>

#include "server/parse/import_cancel.h"

namespace mbstream {

sigset_t BlockStopSignals() {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  return signals;
}

namespace {

timespec ToTimespec(std::chrono::steady_clock::duration left) {
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(left).count();
  return timespec{static_cast<time_t>(ns / 1'000'000'000), static_cast<long>(ns % 1'000'000'000)};
}

}  // namespace

void StopWatchdog::Arm(const sigset_t& signals, std::chrono::milliseconds limit) {
  wake_signal_ = sigismember(&signals, SIGINT) == 1 ? SIGINT : SIGTERM;
  thread_ = std::thread([this, signals, limit] {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    int received = -1;
    // EINTR (a debugger or the leak checker attaching, a handled signal) is not a stop: wait
    // again for what is left of the limit.
    for (;;) {
      const auto left = deadline - std::chrono::steady_clock::now();
      if (left <= std::chrono::steady_clock::duration::zero()) break;
      const timespec wait = ToTimespec(left);
      siginfo_t info;
      received = sigtimedwait(&signals, &info, &wait);
      if (received > 0 || errno != EINTR) break;
    }
    if (disarmed_.load()) return;  // the destructor's wake-up: the shutdown finished
    spdlog::warn("{}; exiting without waiting for the requests still being served",
                 received > 0 ? "a second signal" : "the shutdown took over its limit");
    spdlog::default_logger()->flush();
    std::_Exit(1);
  });
}

StopWatchdog::~StopWatchdog() {
  if (!thread_.joinable()) return;
  disarmed_.store(true);
  // Thread-directed: the watchdog's sigtimedwait takes it; it stays pending until then.
  pthread_kill(thread_.native_handle(), wake_signal_);
  thread_.join();
}

void ServeUntilSignalled(ServerHost& host, const sigset_t& signals, StopWatchdog& watchdog) {
  std::thread signal_waiter([&] {
    int signal = 0;
    sigwait(&signals, &signal);
    spdlog::info("signal {} received", signal == SIGINT ? "SIGINT" : "SIGTERM");
    // A model being imported is abandoned at its next check (import_cancel.h): its call
    // answers UNAVAILABLE and nothing of it is stored, so the shutdown need not wait for it.
    CancelAllImports();
    // A stop is at once: a handler that outlives gRPC's 2 s shutdown deadline (a request
    // still being served) must not hold the process, and a second signal ends it now, during
    // a drain's grace period too. The store stays consistent (SQLite's journal, PostgreSQL's
    // transactions; runs are marked INTERRUPTED at the next start).
    constexpr std::chrono::milliseconds kShutdownLimit{5000};
    if (signal == SIGTERM) {
      watchdog.Arm(signals, kShutdownLimit + std::chrono::milliseconds(
                                                 static_cast<int64_t>(1000.0 * host.grace_s())));
      host.Drain();
    } else {
      watchdog.Arm(signals, kShutdownLimit);
    }
    host.Shutdown();
  });
  host.Wait();
  signal_waiter.join();
}

}  // namespace mbstream

#include "server/app/server_signals.h"

#include <spdlog/spdlog.h>

#include <cstdlib>
#include <ctime>
#include <thread>

namespace mbstream {

sigset_t BlockStopSignals() {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  return signals;
}

void ServeUntilSignalled(ServerHost& host, const sigset_t& signals) {
  std::thread signal_waiter([&] {
    int signal = 0;
    sigwait(&signals, &signal);
    spdlog::info("signal {} received", signal == SIGINT ? "SIGINT" : "SIGTERM");
    if (signal == SIGTERM) host.Drain();
    // A stop is at once: a handler that outlives gRPC's 2 s shutdown deadline (a request
    // still being served) must not hold the process, and a second signal ends it now. The
    // store stays consistent (SQLite's journal, PostgreSQL's transactions; runs are marked
    // INTERRUPTED at the next start).
    std::thread([signals] {
      const timespec deadline{5, 0};
      siginfo_t info;
      const bool again = sigtimedwait(&signals, &info, &deadline) > 0;
      spdlog::warn("{}; exiting without waiting for the requests still being served",
                   again ? "a second signal" : "the shutdown took over 5 s");
      spdlog::default_logger()->flush();
      std::_Exit(1);
    }).detach();
    host.Shutdown();
  });
  host.Wait();
  signal_waiter.join();
}

}  // namespace mbstream

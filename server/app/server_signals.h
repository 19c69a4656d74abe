// How mbstream-server stops: SIGTERM drains (its runs get --grace-s to end), SIGINT stops
// at once (runs INTERRUPTED); either cancels every model import (CancelAllImports,
// server/parse/import_cancel.h), so a submit mid-parse does not hold the shutdown. A second
// signal (during a drain too), or 5 s after the shutdown began (after the drain's grace
// period), exits without waiting for requests still being served.
#pragma once

#include <pthread.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <thread>

#include "server/app/server_host.h"

namespace mbstream {

// Blocks SIGINT and SIGTERM in the calling thread and every thread it starts from now on
// (call first, before any thread), and returns them for ServeUntilSignalled.
sigset_t BlockStopSignals();

// Once armed, ends the process (std::_Exit(1)) when one of `signals` arrives again or
// `limit` passes before it is destroyed; the destructor disarms it and joins its thread, so
// nothing of it runs while the program's objects are destroyed at exit. Wakes on events
// only: a signal, the deadline, or the destructor's thread-directed signal.
class StopWatchdog {
 public:
  StopWatchdog() = default;
  StopWatchdog(const StopWatchdog&) = delete;
  StopWatchdog& operator=(const StopWatchdog&) = delete;
  ~StopWatchdog();

  // Called once, from a thread where `signals` are blocked.
  void Arm(const sigset_t& signals, std::chrono::milliseconds limit);

 private:
  std::thread thread_;
  std::atomic<bool> disarmed_{false};
  int wake_signal_ = 0;
};

// Serves until `signals` arrive, then arms `watchdog` (5 s, plus the grace period for a
// drain) and drains or shuts `host` down;
// returns when it stopped. Keep `watchdog` alive until the host is destroyed.
void ServeUntilSignalled(ServerHost& host, const sigset_t& signals, StopWatchdog& watchdog);

}  // namespace mbstream

// The few threads that drive the service's streaming reactors (subscribe_call.h,
// watch_call.h): tasks posted now (a subscription got an event, a control came) and tasks
// due at a time (a replay's next frame, a progress event, a start deadline). A stream holds
// no thread of its own: it is a reactor on gRPC's callback API that these threads and
// gRPC's own poke. Tasks must not block for long (they share the threads). Thread-safe.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace mbstream {

class StreamPump {
 public:
  using Clock = std::chrono::steady_clock;

  explicit StreamPump(int threads = 2);
  ~StreamPump();  // drops the tasks not run yet, joins the threads
  StreamPump(const StreamPump&) = delete;
  StreamPump& operator=(const StreamPump&) = delete;

  void Post(std::function<void()> task) { PostAt(Clock::time_point::min(), std::move(task)); }
  // Runs `task` at `due` (or as soon after as a thread is free); tasks due alike run in the
  // order they were posted.
  void PostAt(Clock::time_point due, std::function<void()> task);

 private:
  void Work();

  std::mutex mutex_;
  std::condition_variable changed_;
  std::multimap<Clock::time_point, std::function<void()>> tasks_;
  bool stopping_ = false;
  std::vector<std::thread> threads_;
};

// When a reactor's RunStep runs on the pump: soon (Poke; pokes while one is pending are
// one) or at a time (WakeAt; only the latest time asked for counts). A member of the
// reactor, which `self` keeps alive until the step ran.
class PumpSteps {
 public:
  template <typename Reactor>
  void Poke(StreamPump& pump, std::shared_ptr<Reactor> self) {
    if (poke_pending_.exchange(true)) return;
    pump.Post([this, self = std::move(self)] {
      poke_pending_ = false;
      self->RunStep();
    });
  }
  // With `mutex` (the reactor's) held.
  template <typename Reactor>
  void WakeAt(StreamPump& pump, StreamPump::Clock::time_point due, std::shared_ptr<Reactor> self,
              std::mutex& mutex) {
    const uint64_t wake = ++wake_;
    pump.PostAt(due, [this, self = std::move(self), wake, &mutex] {
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (wake != wake_) return;  // a later step asked for another time
      }
      self->RunStep();
    });
  }

 private:
  std::atomic<bool> poke_pending_{false};
  uint64_t wake_ = 0;  // the latest WakeAt (the reactor's mutex)
};

}  // namespace mbstream

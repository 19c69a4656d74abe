// The few threads that drive the service's streaming reactors (subscribe_call.h,
// watch_call.h): tasks posted now (a subscription got an event, a control came) and tasks
// due at a time (a replay's next frame, a progress event, a start deadline). A stream holds
// no thread of its own: it is a reactor on gRPC's callback API that these threads and
// gRPC's own poke. Tasks must not block for long (they share the threads). Thread-safe.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <map>
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

}  // namespace mbstream

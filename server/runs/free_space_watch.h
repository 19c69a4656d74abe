// Watches the free space of the data directory's disk against --min-free-mb (free_space.h) so
// that the server can say, before anyone asks for a run, that it would refuse new runs: the
// health service's new-runs status (server_host.cc) follows it. A check every few seconds on a
// thread of its own, or Check() at once (tests, after a deletion). gRPC-free.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>

#include "server/runs/free_space.h"

namespace mbstream {

class FreeSpaceWatch {
 public:
  // Called with `enough` (free space >= the minimum, or unknown) when it changes, and once
  // when set.
  using Listener = std::function<void(bool enough)>;

  // `source` empty or `min_free_bytes` <= 0: always enough.
  FreeSpaceWatch(FreeSpaceSource source, int64_t min_free_bytes);
  ~FreeSpaceWatch();  // Stop()
  FreeSpaceWatch(const FreeSpaceWatch&) = delete;
  FreeSpaceWatch& operator=(const FreeSpaceWatch&) = delete;

  // Reads the free space now, tells the listener when `enough` changed; returns `enough`.
  bool Check();
  void SetListener(Listener listener);
  // Check() every `period_s` on a thread of its own until Stop.
  void Start(double period_s);
  void Stop();

  // The free bytes as last read (nullopt: unknown or never read), and the minimum.
  std::optional<int64_t> free_bytes() const;
  int64_t min_free_bytes() const { return min_free_bytes_; }
  bool enough() const;

 private:
  const FreeSpaceSource source_;
  const int64_t min_free_bytes_;
  mutable std::mutex mutex_;
  std::optional<int64_t> free_bytes_;
  bool enough_ = true;
  Listener listener_;
  std::mutex listener_mutex_;  // one listener call at a time, in order
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace mbstream

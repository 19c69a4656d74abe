// When each frame went out on one stream, for the probe round-trip latency.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace mbstream {

// A ring of the last 8192 frames sent (run id hash, seq, time). Thread-safe: the stream's
// writer records, its reader looks up.
class SentTimes {
 public:
  using Clock = std::chrono::steady_clock;

  void Record(const std::string& run_id, int64_t seq, Clock::time_point sent) {
    std::lock_guard<std::mutex> lock(mutex_);
    entries_[static_cast<size_t>(seq) % entries_.size()] = {Hash(run_id), seq, sent};
  }
  // Microseconds from the frame's send to `received`, or -1 when it is no longer known.
  int64_t LatencyUs(const std::string& run_id, int64_t seq, Clock::time_point received) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const Entry& e = entries_[static_cast<size_t>(seq) % entries_.size()];
    if (e.seq != seq || e.run != Hash(run_id)) return -1;
    return std::chrono::duration_cast<std::chrono::microseconds>(received - e.sent).count();
  }

 private:
  struct Entry {
    size_t run = 0;
    int64_t seq = -1;
    Clock::time_point sent;
  };
  static size_t Hash(const std::string& s) { return std::hash<std::string>{}(s); }
  mutable std::mutex mutex_;
  std::array<Entry, 8192> entries_{};
};

}  // namespace mbstream

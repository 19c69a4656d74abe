// The frames of the runs that ended last on this replica, kept in memory for the GetResult
// that usually follows a run's end at once (a sweep fetches every result): served from here,
// the result is not read back from the store. Only a result stored whole in its run's final
// transaction (one chunk) and final for good (any final state but INTERRUPTED) is kept, as stored
// (frame_chunks.h), oldest out first beyond `max_bytes`. Thread-safe.
#pragma once

#include <cstddef>
#include <deque>
#include <mutex>
#include <string>
#include <unordered_map>

namespace mbstream {

class RecentResults {
 public:
  explicit RecentResults(std::size_t max_bytes) : max_bytes_(max_bytes) {}

  // Keeps run `run_id`'s stored chunk blob (its every frame), replacing one kept before.
  void Put(const std::string& run_id, std::string chunk);
  // Copies run `run_id`'s chunk blob into `chunk`; false when it is not kept.
  bool Get(const std::string& run_id, std::string& chunk) const;

  std::size_t bytes() const;

 private:
  const std::size_t max_bytes_;
  mutable std::mutex mutex_;
  std::unordered_map<std::string, std::string> chunks_;
  std::deque<std::string> order_;  // run ids, oldest first
  std::size_t bytes_ = 0;
};

}  // namespace mbstream

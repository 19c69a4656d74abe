// The runs that ended last on this replica, kept in memory for the GetResult that usually
// follows a run's end at once (a sweep fetches every result): their final info and their
// frames are served from here, not read back from the store. Only a result stored whole in its
// run's final transaction (one chunk) and final for good (any final state but INTERRUPTED: an
// ended run's info and frames never change again) is kept, as stored (frame_chunks.h), oldest
// out first beyond `max_bytes` (the chunks' bytes and the infos' serialized sizes).
// Thread-safe.
#pragma once

#include <cstddef>
#include <deque>
#include <mutex>
#include <string>
#include <unordered_map>

#include "mbstream/v1/run.pb.h"

namespace mbstream {

class RecentResults {
 public:
  explicit RecentResults(std::size_t max_bytes) : max_bytes_(max_bytes) {}

  // Keeps run `info.id()`'s final info and stored chunk blob (its every frame), replacing
  // what was kept for it before.
  void Put(const v1::RunInfo& info, std::string chunk);
  // Forgets the run (deleted from the store); nothing when it is not kept.
  void Erase(const std::string& run_id);
  // Copies the run's chunk blob into `chunk`; false when it is not kept.
  bool Get(const std::string& run_id, std::string& chunk) const;
  // Copies the run's final info into `info`; false when it is not kept.
  bool GetInfo(const std::string& run_id, v1::RunInfo& info) const;

  std::size_t bytes() const;

 private:
  struct Kept {
    v1::RunInfo info;
    std::string chunk;
    std::size_t bytes = 0;
  };

  void EraseLocked(const std::string& run_id);  // mutex_ held

  const std::size_t max_bytes_;
  mutable std::mutex mutex_;
  std::unordered_map<std::string, Kept> kept_;
  std::deque<std::string> order_;  // run ids, oldest first
  std::size_t bytes_ = 0;
};

}  // namespace mbstream

// RunManager's stored results (run_results.cc), read piece by piece: a long run is never in
// memory at once. Info throws RequestError: kNotFound, or kFailedPrecondition while the run
// is queued or running. Frames reads stored chunk `index` (or the next one) into `data` and
// appends its frames' serialized bytes (views into `data`) to `frames`; it returns the index
// to ask for next, nullopt after the last (Store::GetSerializedFrames).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mbstream/v1/frame.pb.h"
#include "mbstream/v1/run.pb.h"

namespace mbstream {

class RunManager;

class RunResults {
 public:
  RunResults(const RunResults&) = delete;
  RunResults& operator=(const RunResults&) = delete;

  v1::RunInfo Info(const std::string& run_id) const;
  std::optional<int64_t> Frames(const std::string& run_id, int64_t index, std::string& data,
                                std::vector<std::string_view>& frames) const;
  std::vector<v1::ProbeReport> Probes(const std::string& run_id) const;
  // Forgets what this replica keeps of ended run `run_id` in memory (RecentResults, a final
  // state not stored yet), after the run was deleted from the store (run_deleter.h): later
  // reads ask the store.
  void Forget(const std::string& run_id);
  // Hands memory freed after a run or a result back to the system (SQLite's page cache,
  // glibc's arenas: release_memory.h).
  void ReleaseMemory() const;

 private:
  friend class RunManager;
  explicit RunResults(RunManager& manager) : m_(manager) {}
  RunManager& m_;
};

}  // namespace mbstream

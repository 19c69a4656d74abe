// The final states of runs that the store refused to record (a full disk: DiskFullError, or
// any store failure), kept in memory so that the server still shows each run ended as it is
// (GetRun, WatchRun, GetResult and their waits: docs/reliability.md, "a full disk"), and
// written again until the store takes them (Retry, from the sweep feeder's rounds: about every
// second, and after every run's end). A restart before then marks such a run INTERRUPTED, as
// any run its store shows unfinished. Thread-safe.
#pragma once

#include <map>
#include <mutex>
#include <string>

#include "mbstream/v1/run.pb.h"

namespace mbstream {

class Store;

class PendingFinals {
 public:
  // Keeps run `info.id()`'s final info (replacing one kept before).
  void Add(const v1::RunInfo& info);
  // Forgets the run (deleted from the store: never written again).
  void Erase(const std::string& run_id);
  // Copies the run's final info into `info`; false when none is pending.
  bool Find(const std::string& run_id, v1::RunInfo& info) const;
  // Writes each pending info again (Store::PutRun); those the store took are forgotten.
  // Returns how many are still pending.
  size_t Retry(Store& store);
  size_t size() const;

 private:
  mutable std::mutex mutex_;
  std::map<std::string, v1::RunInfo> pending_;  // by run id
  std::mutex retry_mutex_;                      // one Retry at a time
};

}  // namespace mbstream

// Announces to follow streams the runs that other replicas of a shared store integrate
// (docs/cluster.md, "Follow"): while someone follows, it reads the store's RUNNING runs every
// `period` and calls `announce` once for each run (and attempt) that another replica claimed
// after the first follower attached. Without followers it reads nothing; a replica with a
// private (SQLite) store has no ClusterFollow at all.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>

#include "mbstream/v1/run.pb.h"

namespace mbstream {

class Store;

class ClusterFollow {
 public:
  // `store` is not owned. `wanted` says whether any follower is attached (called without
  // this object's lock); `announce` gets each run claimed elsewhere, from this object's thread.
  ClusterFollow(Store* store, std::string replica_id, std::chrono::duration<double> period,
                std::function<bool()> wanted, std::function<void(const v1::RunInfo&)> announce);
  ~ClusterFollow();  // Stop()

  // A follower attaches: reads the store's running runs; when no follower was attached
  // before, notes them as seen (runs claimed from now on are announced). Returns the newest
  // run running on another replica now (none when the store failed), so that a follower
  // attached during a run sees that run as it would a run of its own replica.
  std::optional<v1::RunInfo> Attach();
  void Stop();  // joins the thread; idempotent

 private:
  void Loop();
  // The runs running now, by "id/attempt"; announces those of other replicas not seen yet
  // when `announce_new`; notes them as seen when `note_seen`. Returns the newest one of
  // another replica; none when the store failed (logged once until it answers again).
  std::optional<v1::RunInfo> Look(bool announce_new, bool note_seen);

  Store* const store_;
  const std::string replica_id_;
  const std::chrono::duration<double> period_;
  const std::function<bool()> wanted_;
  const std::function<void(const v1::RunInfo&)> announce_;

  std::mutex mutex_;
  std::condition_variable wake_;
  bool active_ = false;    // followers were attached at the last look
  uint64_t attaches_ = 0;  // Attach calls (a follower attached while the loop looked)
  bool stop_ = false;
  bool store_failed_ = false;
  std::set<std::string> seen_;  // "id/attempt" of the runs running at the last look
  std::thread thread_;
};

}  // namespace mbstream

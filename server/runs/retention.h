// Retention (mbstream-server --retain-runs N, --retain-days D): ended runs beyond the newest N,
// or ended more than D days ago, are deleted in the background, oldest first, one run per store
// transaction (RunDeleter::DeleteIfEnded: live runs' writes wait for one small transaction at
// a time). Never a run marked keep (RunInfo.keep) nor one queued or running; kept runs do not
// count against N. RetentionPlan is what a pass would delete now (the dry run). gRPC-free.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "mbstream/v1/run.pb.h"

namespace mbstream {

class Store;
class RunDeleter;

struct RetentionPolicy {
  int64_t retain_runs = 0;   // keep the newest this many ended, unkept runs; 0: no count limit
  double retain_days = 0.0;  // delete ended runs older than this (by ended_unix_ms); 0: none
  bool active() const { return retain_runs > 0 || retain_days > 0.0; }
};

// Of `runs` (oldest first, as Store::ListRuns), those `policy` deletes at `now_unix_ms`,
// oldest first.
std::vector<v1::RunInfo> RetentionPlan(const std::vector<v1::RunInfo>& runs,
                                       const RetentionPolicy& policy, int64_t now_unix_ms);

class Retention {
 public:
  using Clock = std::function<int64_t()>;  // Unix ms now

  // None is owned. `clock`: Unix ms now (the system's when empty; tests pass a manual one).
  Retention(Store* store, const RunDeleter* deleter, RetentionPolicy policy, Clock clock = {});
  ~Retention();  // Stop()
  Retention(const Retention&) = delete;
  Retention& operator=(const Retention&) = delete;

  // What a pass would delete now (nothing is deleted).
  std::vector<v1::RunInfo> Plan() const;
  // One pass: deletes what Plan() lists (each run read again first: marked keep meanwhile, it
  // stays). Returns how many runs it deleted. A store failure is logged and ends the pass.
  int Sweep();
  // Calls Sweep every `period_s` on a thread of its own (nothing when the policy is
  // inactive), until Stop.
  void Start(double period_s);
  void Stop();

  const RetentionPolicy& policy() const { return policy_; }

 private:
  Store* store_;
  const RunDeleter* deleter_;
  const RetentionPolicy policy_;
  Clock clock_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace mbstream

// RunManager's subscriptions (run_subscriptions.cc) over FanOut and the run queue. A
// subscription counts against limits.max_subscribers from New (RESOURCE_EXHAUSTED at the
// limit) until Unsubscribe, attached to something or not. AttachRun: the run's events
// (started if `send_started`, latest frame, frames, ended); an ended run gives started +
// ended at once; NOT_FOUND for an unknown run. AttachFollow: every run that starts from now
// on, and the one running now (the newest; with a shared store, the newest of the cluster's
// when none runs here), each with started/frames/ended, each exactly once. SubscribeRun =
// New + AttachRun. And the viewers' probe reports for the runs they watch.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "mbstream/v1/frame.pb.h"
#include "mbstream/v1/run.pb.h"
#include "server/runs/subscription.h"

namespace mbstream {

class RunManager;

class RunSubscriptions {
 public:
  RunSubscriptions(const RunSubscriptions&) = delete;
  RunSubscriptions& operator=(const RunSubscriptions&) = delete;

  std::shared_ptr<Subscription> New();
  void AttachRun(const std::shared_ptr<Subscription>& subscriber, const std::string& run_id,
                 bool send_started);
  void AttachFollow(const std::shared_ptr<Subscription>& subscriber);
  std::shared_ptr<Subscription> SubscribeRun(const std::string& run_id, bool send_started);
  void Unsubscribe(const std::shared_ptr<Subscription>& subscriber);
  int count() const;
  // A viewer's checked probe reports (latency already measured), for its run's probe
  // recorder (stored in batches while the run integrates, the last batch when it ends).
  // False (nothing kept) when the run is not integrating or waiting for its last probes any
  // more, or already holds limits.max_probe_reports reports.
  bool AddProbes(const std::string& run_id, const std::vector<v1::ProbeReport>& reports);

 private:
  friend class RunManager;
  explicit RunSubscriptions(RunManager& manager) : m_(manager) {}
  // False when no run of this replica is running (the follower waits for the next).
  bool AttachLocalFollow(const std::shared_ptr<Subscription>& subscriber);
  RunManager& m_;
};

}  // namespace mbstream

// RunManager's subscriptions (run_subscriptions.h): FanOut's subscriptions attached to a run
// of the run queue, or following every run (this replica's, and with a shared store the
// cluster's: cluster_follow.h); the viewers' probe reports for a run's recorder.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "server/runs/cluster_follow.h"
#include "server/runs/request_error.h"
#include "server/runs/run_manager.h"
#include "server/runs/run_subscriptions.h"

namespace mbstream {

std::shared_ptr<Subscription> RunSubscriptions::New() { return m_.fan_out_.NewSubscription(); }

void RunSubscriptions::AttachRun(const std::shared_ptr<Subscription>& subscriber,
                                 const std::string& run_id, bool send_started) {
  switch (m_.queue_.Attach(subscriber, run_id, send_started)) {
    case RunQueue::Attached::kAttached:
      return;
    case RunQueue::Attached::kNotFound:
      throw UnknownRunError(run_id);
    case RunQueue::Attached::kNotHere:
      break;
  }
  // Ended and stored (a run leaves the queue's runs only after it is stored and has ended),
  // or on another replica (not followed here yet: docs/cluster.md).
  if (send_started) subscriber->Push({StreamEvent::Kind::kRunStarted, run_id, nullptr});
  subscriber->Push({StreamEvent::Kind::kRunEnded, run_id, nullptr});
}

bool RunSubscriptions::AttachLocalFollow(const std::shared_ptr<Subscription>& subscriber) {
  // In one step with the worker's marking a run RUNNING and attaching the followers
  // (FanOut::AnnounceStart): the follower sees each run exactly once, here or from the worker.
  return m_.fan_out_.Follow(subscriber, [this] { return m_.queue_.NewestRunning(); });
}

void RunSubscriptions::AttachFollow(const std::shared_ptr<Subscription>& subscriber) {
  const bool running_here = AttachLocalFollow(subscriber);
  if (!m_.cluster_follow_) return;
  // The runs other replicas claim from now on; and, with none running here, the newest one
  // running elsewhere now (the follow relays open each run once, whoever announces it).
  const std::optional<v1::RunInfo> elsewhere = m_.cluster_follow_->Attach();
  if (!running_here && elsewhere) {
    subscriber->Push({StreamEvent::Kind::kRemoteRun, elsewhere->id(), nullptr});
  }
}

std::shared_ptr<Subscription> RunSubscriptions::SubscribeRun(const std::string& run_id,
                                                             bool send_started) {
  std::shared_ptr<Subscription> subscriber = New();
  try {
    AttachRun(subscriber, run_id, send_started);
  } catch (...) {
    Unsubscribe(subscriber);
    throw;
  }
  return subscriber;
}

void RunSubscriptions::Unsubscribe(const std::shared_ptr<Subscription>& subscriber) {
  m_.fan_out_.Unsubscribe(subscriber);
}

int RunSubscriptions::count() const { return m_.fan_out_.subscriber_count(); }

bool RunSubscriptions::AddProbes(const std::string& run_id,
                                 const std::vector<v1::ProbeReport>& reports) {
  std::shared_ptr<Run> run = m_.FindActive(run_id);
  return run && run->probes().Add(reports);
}

}  // namespace mbstream

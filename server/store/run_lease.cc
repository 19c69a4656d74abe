#include "server/store/run_lease.h"

#include <algorithm>

namespace mbstream {
namespace {

// A run that ran has had one attempt at least (one written by a server before the queue
// counted attempts has 0).
bool HasAttemptsLeft(const v1::RunInfo& info) {
  return std::max(1, info.attempts()) < 1 + info.spec().retries();
}

// Back to the queue for the next attempt: the last attempt's progress is forgotten (its
// frames are replaced by the next attempt's), the replica fields keep naming who had it.
void Requeue(v1::RunInfo& info, const std::string& why) {
  info.set_state(v1::QUEUED);
  info.set_message(why + "; queued again (attempt " + std::to_string(info.attempts() + 1) + " of " +
                   std::to_string(1 + info.spec().retries()) + ")");
  info.clear_stats();
  info.set_frames(0);
  info.set_t_s(0.0);
  info.set_started_unix_ms(0);
  info.set_ended_unix_ms(0);  // a queued run has not ended (the hand-back stamped it)
}

std::string ReplicaName(const v1::RunInfo& info) {
  return "replica " + info.replica() +
         (info.replica_address().empty() ? "" : " (" + info.replica_address() + ")");
}

v1::RunState EndOrRequeue(v1::RunInfo& info, int64_t now_unix_ms, const std::string& why,
                          const std::string& interrupted_message) {
  if (HasAttemptsLeft(info)) {
    Requeue(info, why);
  } else {
    info.set_state(v1::INTERRUPTED);
    info.set_message(interrupted_message);
    info.set_ended_unix_ms(now_unix_ms);
  }
  return info.state();
}

}  // namespace

std::string LeaseHolder(const v1::RunInfo& info) {
  return info.replica() + "/" + std::to_string(info.attempts());
}

void ApplyClaim(v1::RunInfo& info, const RunLease& lease) {
  info.set_state(v1::RUNNING);
  info.set_started_unix_ms(lease.now_unix_ms);
  info.set_replica(lease.replica);
  info.set_replica_address(lease.address);
  info.set_attempts(info.attempts() + 1);
}

v1::RunState ApplyLeaseExpired(v1::RunInfo& info, int64_t now_unix_ms, const std::string& reaper) {
  const std::string why =
      ReplicaName(info) + " stopped renewing its lease on this run (it died or lost the store)";
  return EndOrRequeue(info, now_unix_ms, why,
                      why + "; replica " + reaper +
                          " marked it INTERRUPTED when the lease expired. The frames stored "
                          "so far are kept; start the run again, or give spec.retries to "
                          "have it queued again");
}

v1::RunState ApplyHandBack(v1::RunInfo& info, int64_t now_unix_ms, const std::string& reason) {
  return EndOrRequeue(info, now_unix_ms, ReplicaName(info) + " handed the run back: " + reason,
                      reason);
}

}  // namespace mbstream

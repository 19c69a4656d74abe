// The run queue's rules, shared by both stores: what claiming a queued run and the expiry of
// a replica's lease do to a run's info (docs/cluster.md). Times are Unix epoch milliseconds
// given by the caller, so tests drive them with their own clock.
#pragma once

#include <cstdint>
#include <string>

#include "mbstream/v1/run.pb.h"

namespace mbstream {

// A replica's claim on a run: who holds it, where it serves, and until when.
struct RunLease {
  std::string replica;  // the replica's id (RunInfo.replica)
  std::string address;  // host:port it advertises (RunInfo.replica_address)
  int64_t now_unix_ms = 0;
  int64_t expires_unix_ms = 0;  // the lease ends unless renewed before
};

// The holder of a claimed run's lease: its replica and attempt ("replica/attempt"), so that a
// replica never mistakes a later claim of the same run (after a re-queue) for its own.
std::string LeaseHolder(const v1::RunInfo& info);

// A queued run claimed under `lease`: RUNNING, started now, the replica and its address
// recorded, one more attempt.
void ApplyClaim(v1::RunInfo& info, const RunLease& lease);

// A RUNNING run whose lease expired at `now_unix_ms`, found by replica `reaper`: QUEUED again
// while it has attempts left (1 + spec.retries), else INTERRUPTED, each with a message naming
// the replica that held it. Returns the new state.
v1::RunState ApplyLeaseExpired(v1::RunInfo& info, int64_t now_unix_ms, const std::string& reaper);

// A run its replica hands back (drained): QUEUED while it has attempts left, else INTERRUPTED
// with `reason`. Returns the new state.
v1::RunState ApplyHandBack(v1::RunInfo& info, int64_t now_unix_ms, const std::string& reason);

}  // namespace mbstream

// RunManager's replays of stored runs (run_replays.cc; replay.proto): whether a run is queued
// or running now, a cursor over an ended run's stored frames, the replays' probe sets (a new
// unique set id, a recorder that creates a set and adds its reports in batches, the sets of a
// run, one set's reports) and replays to the follow streams.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "mbstream/v1/replay.pb.h"
#include "mbstream/v1/run.pb.h"
#include "server/runs/probe_recorder.h"
#include "server/runs/replay_cursor.h"

namespace mbstream {

class RunManager;

class RunReplays {
 public:
  RunReplays(const RunReplays&) = delete;
  RunReplays& operator=(const RunReplays&) = delete;

  bool IsActive(const std::string& run_id) const;
  // A cursor over an ended run's stored frames (`info` from RunResults::Info).
  std::unique_ptr<ReplayCursor> Open(const v1::RunInfo& info) const;
  std::string NewProbeSetId() const;
  // A recorder of a replay's probe reports, opened: probe set `set` is created in the store
  // with its first batch, the reports added in batches as they come (probe_recorder.h).
  std::unique_ptr<ProbeRecorder> RecordProbeSet(const v1::ProbeSet& set) const;
  // The sets of a run (kNotFound for an unknown run) and one set's reports (kNotFound when
  // the set is not one of the run's).
  std::vector<v1::ProbeSet> ProbeSets(const std::string& run_id) const;
  std::vector<v1::ProbeReport> ProbeSetReports(const std::string& run_id,
                                               const std::string& set_id) const;
  // Streams the ended run `run_id` to the followers attached now (started, its frames paced
  // at `speed_x` simulated s per wall s, ended), as if it were running, on a thread of its
  // own; returns its info at once. Throws RunResults::Info's errors, kFailedPrecondition for
  // a run with no frames. Probe reports of a replayed run are refused (it is stored already).
  v1::RunInfo ToFollowers(const std::string& run_id, double speed_x);

 private:
  friend class RunManager;
  explicit RunReplays(RunManager& manager) : m_(manager) {}
  RunManager& m_;
};

}  // namespace mbstream

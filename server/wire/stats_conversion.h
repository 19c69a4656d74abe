// Run statistics and status between the core (RunStats, RunStatus) and the wire.
#pragma once

#include "mbstream/v1/run.pb.h"
#include "server/sim/run_result.h"

namespace mbstream {

// FINISHED <-> kFinished, ...; the wire's QUEUED/RUNNING/INTERRUPTED have no core status.
v1::RunState RunStateFromStatus(RunStatus status);
// True for the states a run ends in (FINISHED ... INTERRUPTED).
bool IsFinalState(v1::RunState state);

// The statistics as a message. Non-finite numbers become -1 ("unknown") or 0, never NaN.
v1::RunStats StatsToProto(const RunStats& stats);

// A run's summary (RunStats::summary) and back; non-finite numbers as in StatsToProto.
void SummaryToProto(const RunSummary& summary, v1::RunSummary* out);
RunSummary SummaryFromProto(const v1::RunSummary& in);

// The core's view of a finished run's info: statistics, status (QUEUED/RUNNING -> kFailed)
// and message.
RunStats StatsFromProto(const v1::RunInfo& info);

}  // namespace mbstream

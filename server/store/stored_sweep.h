// A sweep as the store holds it (schema version 8, the sweeps table): what StartSweep was
// given and how far its points are queued. The server feeds it (server/runs/sweep_feeder.h):
// points [0, next_point) have a run each (runs.sweep_id, runs.sweep_point), the others are
// expanded from `definition` when a place in its window frees up.
#pragma once

#include <cstdint>
#include <string>

namespace mbstream {

struct StoredSweep {
  std::string id;  // "s-..."
  std::string model_id;
  std::string owner;  // the token's id that started it (RunInfo.owner of its runs)
  int64_t created_unix_ms = 0;
  int32_t total_points = 0;
  int32_t next_point = 0;       // the first point without a run
  int32_t window = 0;           // most of its runs QUEUED or RUNNING at once
  bool cancelled = false;       // CancelSweep: no more points are queued
  std::string definition;       // serialized v1.SweepDefinition (empty unless asked for)
  int32_t unfinished_runs = 0;  // its runs QUEUED or RUNNING now (as read)
};

// How Store::AddSweepRuns went.
enum class SweepFeed {
  kAdded,    // the runs are stored and the sweep's next_point moved past them
  kIdTaken,  // a run id is taken: nothing stored (new ids, again)
  kRefused,  // the sweep moved on (another replica fed those points), is cancelled, unknown,
             // or its window has no room for them: nothing stored (read the sweep again)
};

}  // namespace mbstream

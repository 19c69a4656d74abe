// The limits a server enforces on requests (set from mbstream-server's flags).
#pragma once

#include <cstdint>

namespace mbstream {

struct ServerLimits {
  // A model bundle: the defaults hold a PR2 (46 MB of visual meshes, about twice that with
  // its collision meshes).
  int64_t max_model_bytes = int64_t{128} << 20;  // URDF + scene + assets of one model, bytes
  int64_t max_asset_bytes = int64_t{64} << 20;   // one asset (mesh file), bytes
  int max_assets = 1000;                         // assets of one model
  int max_links = 256;                           // frames (links and named points) of one model
  int workers = 2;                               // runs integrating at the same time
  int max_queued_runs = 64;                      // runs waiting for a worker
  int max_subscribers = 64;                      // Subscribe + WatchRun streams at the same time
  double max_duration_s = 24 * 3600.0;           // s, simulated time of one run
  int64_t max_output_frames = 2'000'000;         // frames of one run
  long max_internal_steps = 100'000'000;         // integrator steps of one run (budget cap)
  double max_run_cpu_s = 3600.0;                 // s of CPU of one run (budget cap)
  int subscriber_queue_frames = 4096;            // frames buffered per subscriber before dropping
  double probe_grace_s = 2.0;             // s a finished run waits for its viewers' last probes
  double subscribe_start_s = 10.0;        // s a Subscribe stream may take to send `start`
  int64_t max_probe_reports = 1'000'000;  // probe reports kept for one run
  int max_models = 1000;                  // models submitted by users, stored (built-ins apart)
  int64_t max_total_model_bytes = int64_t{4} << 30;  // their total stored size, bytes
  int compiled_models_cached = 16;  // compiled models kept in memory (runs keep theirs)
  // Bytes of ended runs' frames kept in memory for their GetResult (recent_results.h): a
  // sweep's window of 64 runs of 401 frames of a 6-joint arm is 5.4 MB.
  int64_t recent_results_bytes = int64_t{16} << 20;
  // s of wall time after which a running run's frames not yet stored go to the store even if
  // their chunk is not full (4,096 frames): a crash loses at most this much of a run. 0:
  // only full chunks are stored while the run runs. The viewers' probe reports are stored
  // in batches on the same interval (ProbeRecorder; 512 reports make a batch sooner).
  double frame_flush_s = 1.0;
  // Bytes that must stay free on the disk of a SQLite store's data directory for a new run to
  // start (--min-free-mb; free_space.h): below it StartRun(s) answer RESOURCE_EXHAUSTED. 0:
  // no check. A margin for the runs already running, SQLite's journal and WAL checkpoints.
  int64_t min_free_bytes = int64_t{64} << 20;
};

}  // namespace mbstream

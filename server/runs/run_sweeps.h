// RunManager's sweeps (run_sweeps.cc; docs/cluster.md, "Sweeps"): a sweep the server feeds.
// Start checks every point's values against the spec's fields and the first `window` points
// against the model (InputError or RequestError naming the point), stores the sweep whole
// and queues its first window (as the queue has room); the feeder (sweep_feeder.h) queues
// the rest, at most `window` (0: 32) of its runs queued or running at once, each point's run
// expanded from the stored definition (sweep_plan.h). A later point the model refuses is
// stored as a FAILED run of the sweep. Reads: a sweep's counts and a page of its runs, every
// replica's (the store's indexes of sweep ids), and the mark that it was cancelled.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mbstream/v1/run.pb.h"
#include "mbstream/v1/sweep.pb.h"
#include "server/runs/sweep_plan.h"
#include "server/store/stored_sweep.h"

namespace mbstream {

class RunManager;

class RunSweeps {
 public:
  RunSweeps(const RunSweeps&) = delete;
  RunSweeps& operator=(const RunSweeps&) = delete;

  struct Started {
    std::string id;
    int total_points = 0;
    std::vector<std::string> paths;
    std::vector<v1::RunInfo> runs;  // queued (or FAILED) by this call, in point order
    std::vector<std::vector<std::string>> values;  // each run's values, in paths' order
  };
  // Throws as RunManager::StartMany.
  Started Start(const std::string& model, v1::SweepDefinition definition, int window,
                const std::string& owner);
  // A sweep as the store holds it: its row (nullopt for a sweep an older server started in
  // slices: then `runs` are all its runs), its runs by state (those integrating here as they
  // are now) and a page of its runs, in point order from point `runs_from`, at most
  // `max_runs` (0 = 1,000, at most 1,000), each with its values. Throws kNotFound.
  struct View {
    std::optional<StoredSweep> stored;
    std::map<int, int> states;  // by v1::RunState
    std::vector<v1::RunInfo> runs;
    std::vector<std::string> paths;
    std::vector<std::vector<std::string>> values;  // of each run of `runs` (with `stored`)
  };
  View Get(const std::string& sweep_id, int runs_from, int max_runs) const;
  // The runs of sweep `sweep_id` QUEUED or RUNNING in the store (at most its window).
  std::vector<v1::RunInfo> Unfinished(const std::string& sweep_id) const;
  // The runs of sweep `sweep_id` the store holds (every replica's), in point order, each as
  // RunManager::Get returns it. Empty for an unknown sweep.
  std::vector<v1::RunInfo> Runs(const std::string& sweep_id) const;
  // Records on every stored run of sweep `sweep_id` that the sweep was cancelled
  // (RunInfo.sweep_cancelled; Store::MarkSweepCancelled) and returns how many were marked now.
  int MarkCancelled(const std::string& sweep_id);
  // Whether sweep `sweep_id` was cancelled (a stored run carries the mark), from the store's
  // index alone.
  bool Cancelled(const std::string& sweep_id) const;

 private:
  friend class RunManager;
  explicit RunSweeps(RunManager& manager) : m_(manager) {}
  // The feeder's step: points [first, first + count) of `sweep` (at most what the queue
  // takes) expanded, checked and stored with the sweep's next point in one store
  // transaction, the QUEUED ones queued here. Returns the runs stored, in point order; none
  // when the store refused them (another replica queued them first, the sweep was cancelled
  // or its window is full), the queue is full or stopping, or the disk full.
  std::vector<v1::RunInfo> Feed(const StoredSweep& sweep, const SweepPlan& plan, int first,
                                int count);

  RunManager& m_;
};

}  // namespace mbstream

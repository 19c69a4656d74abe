// The server's side of a sweep (docs/cluster.md, "Sweeps"): a thread that keeps each stored
// sweep's window of runs filled. Each round lists the sweeps with points left to queue
// (Store::ListOpenSweeps, with their unfinished runs counted) and asks its owner to queue the
// next points of each that has room (`feed`: expanded from the stored definition, stored by
// Store::AddSweepRuns, which refuses points another replica queued first). Rounds run when
// woken (a run of this replica changed state, a sweep was started) and every `poll_s` (the
// runs of other replicas sharing the store). Memory: the plans of the sweeps followed, never
// a RunInfo per point. Thread-safe.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "server/runs/sweep_plan.h"
#include "server/store/stored_sweep.h"

namespace mbstream {

class Store;

class SweepFeeder {
 public:
  // Queues points [first, first + count) of `sweep`; false when it could not (refused,
  // queue full, stopping): a later round tries again. Called on the feeder's thread.
  using Feed =
      std::function<bool(const StoredSweep& sweep, const SweepPlan& plan, int first, int count)>;

  // `store` is not owned and must outlive the feeder. Start() starts the thread, which also
  // calls `after_round` (when given) after each round: the owner's other periodic chores.
  SweepFeeder(Store* store, std::chrono::milliseconds poll, Feed feed,
              std::function<void()> after_round = nullptr);
  ~SweepFeeder();  // Stop()

  void Start();
  void Stop();  // joins the thread; idempotent
  void Wake();  // one more round soon

  // The plan of stored sweep `sweep` (read from the store the first time; kept while the
  // sweep is followed, a few more after). Throws InputError when its definition is damaged.
  std::shared_ptr<const SweepPlan> Plan(const StoredSweep& sweep) const;
  // Keeps `plan` for sweep `sweep_id` (RunSweeps::Start has it at hand).
  void Remember(const std::string& sweep_id, std::shared_ptr<const SweepPlan> plan);

  // One round on the caller's thread (tests; the thread runs them otherwise).
  void RunRound();
  // No round runs while the lock is held (RunSweeps::Start queues a new sweep's first window).
  std::unique_lock<std::mutex> HoldRounds() { return std::unique_lock(round_mutex_); }

  // How many points of a sweep with `room` places free and `left` points left one round
  // queues: none until a quarter of its window is free (fewer, larger store transactions),
  // unless the points left fit.
  static int PointsToQueue(int window, int room, int left);

 private:
  void Loop();

  Store* store_;
  const std::chrono::milliseconds poll_;
  const Feed feed_;
  const std::function<void()> after_round_;

  std::mutex round_mutex_;  // one round at a time (the thread's, RunRound's)
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool woken_ = false;
  bool stop_ = false;
  mutable std::map<std::string, std::shared_ptr<const SweepPlan>> plans_;  // by sweep id
  std::thread thread_;
};

}  // namespace mbstream

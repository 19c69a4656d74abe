// Probe reports on their way to the store, for a live run and a replay's probe set alike: the
// reports of a viewer are kept as they arrive and stored in batches, as FrameSpool stores
// frames in chunks: a batch when `batch_reports` reports are at hand, or once `interval` of
// the run clock has passed since the last stored batch (looked at by FlushIfDue: a live run's
// worker calls it with each frame, a replay's reader with each report). A server killed
// mid-run keeps every batch stored before; the end of a run waits only for the last batch
// (Flush).
//
// Each stored batch is logged ("<name>: probe batch <n> stored: <k> reports, <total> in
// all, through frame <seq>"): what the server has answered for good.
//
// Thread-safe: Add from the viewers' stream readers, FlushIfDue and Flush from any thread
// (one batch is written at a time, in the order the reports arrived; a report added while
// a batch is written goes with the next).
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "mbstream/v1/frame.pb.h"
#include "server/runs/run_clock.h"

namespace mbstream {

class ProbeRecorder {
 public:
  // Stores one batch (one store transaction): true when stored; false when the writer may
  // not store any more (a replica whose lease on the run was lost, Store::RenewLease):
  // nothing stored, and the recorder refuses every report from then on. Throws what the
  // store throws.
  using BatchWriter = std::function<bool(const std::vector<v1::ProbeReport>& batch)>;
  static constexpr std::size_t kBatchReports = 512;  // reports per store transaction

  struct Options {
    int64_t max_reports = 1'000'000;  // accepted in all (ServerLimits::max_probe_reports)
    std::size_t batch_reports = kBatchReports;
    // A batch that is not full is stored once this much of the clock's time has passed since
    // the last stored batch (since Open for the first). Zero: full batches and Flush only.
    RunClock::TimePoint::duration interval{};
  };

  // `name` says whose reports these are in the log ("run r-...", "probe set ps-... of run
  // r-..."). `clock` must outlive the recorder.
  ProbeRecorder(std::string name, const RunClock& clock, Options options);
  ProbeRecorder(const ProbeRecorder&) = delete;
  ProbeRecorder& operator=(const ProbeRecorder&) = delete;

  // Batches go to `writer` from now on; the interval runs from now. Reports added before
  // are kept for the first batch.
  void Open(BatchWriter writer);
  // Keeps checked reports (SentFrames::Accept). False, and none kept, once closed, after a
  // store failure or a lost lease, or when they would exceed max_reports.
  bool Add(const std::vector<v1::ProbeReport>& reports);
  // Stores the reports at hand when a batch is full or the interval has passed, unless
  // another thread is storing one now. A store failure does not throw: it is kept in error()
  // and later reports are refused. Returns whether a batch was stored.
  bool FlushIfDue();
  // Stores every report at hand (opened or not: without a writer they are dropped). False
  // when the lease was lost. Throws what the writer throws.
  bool Flush();
  // Refuses later reports (the run has ended) and wakes WaitFor.
  void Close();
  // Waits up to `timeout` until a report for frame `seq` or later was added, or Close.
  void WaitFor(int64_t seq, std::chrono::duration<double> timeout);

  int64_t accepted() const;  // reports kept by Add
  int64_t stored() const;    // of those, in stored batches
  int64_t batches() const;   // batches stored
  bool lease_lost() const;
  std::string error() const;  // why a batch could not be stored; empty while all were

 private:
  // Stores `batch_` (write_mutex_ held). Returns the writer's answer.
  bool Write();

  const std::string name_;
  const RunClock& clock_;
  const Options options_;

  mutable std::mutex mutex_;
  std::condition_variable arrived_;
  BatchWriter writer_;
  std::vector<v1::ProbeReport> pending_;  // added, not yet in a batch
  RunClock::TimePoint last_flush_{};
  int64_t accepted_ = 0;
  int64_t stored_ = 0;
  int64_t batches_ = 0;
  int64_t newest_seq_ = -1;
  bool closed_ = false;
  bool lease_lost_ = false;
  std::string error_;

  std::mutex write_mutex_;              // one batch at a time, in order
  std::vector<v1::ProbeReport> batch_;  // being written (write_mutex_)
};

}  // namespace mbstream

// What a replay's Subscribe stream receives, handed from its reader thread to its writer:
// time controls (a short bounded queue) and probe reports (stored as the replay's probe set by
// the run manager's ProbeRecorder, as a live run's reports are: in batches as they come, the
// set created with its first batch). Thread-safe.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <vector>

#include "mbstream/v1/frame.pb.h"
#include "mbstream/v1/replay.pb.h"
#include "server/runs/probe_recorder.h"
#include "server/runs/run_manager.h"

namespace mbstream {

class ReplayInbox {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr std::size_t kMaxControls = 64;  // queued controls; more are dropped

  // `set` names the probe set (id, run, viewer, scene); limits().max_probe_reports bounds it.
  ReplayInbox(RunManager* runs, v1::ProbeSet set);
  ~ReplayInbox();  // stores the last batch (errors are logged)
  ReplayInbox(const ReplayInbox&) = delete;
  ReplayInbox& operator=(const ReplayInbox&) = delete;

  const v1::ProbeSet& set() const { return set_; }

  // Reader thread.
  void PushControl(const v1::ReplayControl& control);
  // A checked report (SentFrames::Accept): false when the set is full or could not be
  // stored. Stores a batch when one is due.
  bool AddProbe(const v1::ProbeReport& report);
  // The reader has stopped: wakes the writer.
  void Wake();

  // Writer thread: stores the reports at hand when the recorder's interval has passed (a
  // viewer that stopped answering still has its last reports stored).
  void FlushIfDue() { recorder_->FlushIfDue(); }
  // Writer thread: the next control, waiting until `deadline` for one (or a probe report);
  // false when none came.
  bool NextControl(Clock::time_point deadline, v1::ReplayControl* control);
  // The frame of the newest probe report accepted (-1 = none yet): how far the viewer got.
  int64_t answered_seq() const { return answered_seq_; }

 private:
  const v1::ProbeSet set_;
  const std::unique_ptr<ProbeRecorder> recorder_;
  std::mutex mutex_;
  std::condition_variable arrived_;
  std::deque<v1::ReplayControl> controls_;
  bool woken_ = false;
  std::atomic<int64_t> answered_seq_{-1};
  std::vector<v1::ProbeReport> one_;  // reader side only: the report being added
};

}  // namespace mbstream

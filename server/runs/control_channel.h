// The meeting point of a run's worker and the Control stream that commands it (issue 45,
// proto/mbstream/v1/control.proto): the worker's ControlLaw (server/sim/control_law.h) on
// one side, the stream (a reactor on gRPC's callback API, server/service/control_call.h) on
// the other. At each control instant the worker publishes the state, hands it to the stream's
// ControlWriter itself (which starts its write on the worker's thread, without waiting for
// it), and sleeps on a condition variable until the command for that step arrives, the stream
// fails or goes away, the run is cancelled or control_timeout_s passes (no spinning: a timed
// wait, woken by each event). gRPC's thread that reads the command wakes the worker directly:
// a round trip crosses one thread hand-off (reader -> worker) beyond a bare echo. One channel
// per run with external drives, made with the run (Run::control); at most one stream attaches
// to it.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "mbstream/v1/control.pb.h"
#include "mbstream/v1/run.pb.h"
#include "server/sim/control_law.h"

namespace mbstream {

// s, RunSpec.control_timeout_s when absent.
inline constexpr double kDefaultControlTimeoutS = 10.0;

// The stream's side as the channel sees it (installed once the stream's `started` is queued):
// the worker hands each state to Write itself. Neither call blocks (the stream queues the
// message and writes it when gRPC has none in flight) nor calls back into the channel.
class ControlWriter {
 public:
  virtual ~ControlWriter() = default;
  // false when the stream is gone (the run is then cancelled).
  virtual bool Write(const v1::ControlResponse& response) = 0;
  // The run ended (its final info is in the run manager): the stream sends `ended`.
  virtual void Ended() = 0;
};

class ControlChannel : public ControlLaw {
 public:
  // `external` commands per step (the run's external joints); `timeout`: how long the worker
  // waits for a command (and for a stream to attach); `hold_last`: past it, hold the last
  // command and go on; `cancel` (the run's flag, which must outlive the channel) stops a wait.
  ControlChannel(int external, std::chrono::duration<double> timeout, bool hold_last,
                 const std::atomic<bool>* cancel);

  // The worker's side (ControlLaw).
  bool Command(const ControlState& state, double* commands, RunStats* stats) override;
  void Final(const ControlState& state) override;

  // The stream's side. Attach: false when a stream is attached already (or was: one per run).
  bool Attach();
  // From now on the worker hands its states to `writer` (the latest one published before,
  // if unsent, at once; Ended at once if the run ended already). StopWriting: no more, waiting
  // for calls of the writer under way to return.
  void SetWriter(ControlWriter* writer);
  void StopWriting();
  // A command for step `step` (checked by the stream: finite, the right length). Returns "" when
  // taken, or dropped as late for a step whose last command was held (hold_last_command) or
  // after the run stopped (a controller late past its timeout); otherwise the reason it is
  // refused (another step: flooding or out of order), and the run is failed with that reason.
  std::string Deliver(int64_t step, const double* values, size_t count);
  // The stream refused a command: the run fails with `message`.
  void Fail(const std::string& message);
  // The stream closed or was cancelled: the run is cancelled (if it still waits or will).
  void Detach();
  // Wakes a waiting worker to look at the run's cancel flag (RunManager::Cancel).
  void Wake();
  // The run ended (RunManager::Finish): the stream sends `ended` and finishes.
  void Close();
  bool closed() const;

 private:
  const int external_;
  const std::chrono::duration<double> timeout_;
  const bool hold_last_;
  const std::atomic<bool>* cancel_;

  // Hands state_ to the writer if it has not had it (lock held on entry and exit, released
  // around the call).
  void Send(std::unique_lock<std::mutex>& lock);
  // Wakes the worker and StopWriting's wait (lock held or not).
  void NotifyAll();

  mutable std::mutex mutex_;
  std::condition_variable command_cv_;  // the worker waits: a command, a failure, the end
  std::condition_variable stream_cv_;   // StopWriting waits; a Send waits for the one before
  bool attached_ = false;               // a stream attached (once)
  bool detached_ = false;               // ... and went away
  bool closed_ = false;                 // the run ended
  bool stopped_ = false;                // the worker stopped the run (Command returned false)
  std::string failure_;                 // the stream refused a command: the run fails with this
  v1::ControlState state_;              // the latest state published
  int64_t published_ = -1;              // its step (-1: none yet); the final state's is one more
  int64_t written_ = -1;                // the step of the last state handed to the writer
  ControlWriter* writer_ = nullptr;     // the stream's side (null: none attached, or gone)
  int writer_calls_ = 0;                // calls of writer_ under way (outside the lock)
  bool stop_waits_ = false;             // StopWriting waits for them
  v1::ControlResponse out_;             // the message handed to Write (reused)
  bool sending_ = false;                // a Send's Write reads out_ (outside the lock)
  int64_t awaited_ = -1;                // the step the worker waits for a command for (-1: none)
  int64_t held_up_to_ = -1;             // the last step whose command timed out and was held
  int64_t last_taken_ = -1;             // the step of the last command taken
  std::vector<double> command_;         // the last command taken
};

}  // namespace mbstream

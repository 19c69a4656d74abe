#include "server/runs/control_channel.h"

#include "server/sim/run_stop.h"
#include "shared/common/format.h"

namespace mbstream {

namespace {

void ToProto(const ControlState& state, bool final, v1::ControlState* out) {
  out->set_step(state.step);
  out->set_t_s(state.t);
  out->mutable_q()->Assign(state.q->data(), state.q->data() + state.q->size());
  out->mutable_qd()->Assign(state.qd->data(), state.qd->data() + state.qd->size());
  out->mutable_tcp()->set_x(state.tcp.x());
  out->mutable_tcp()->set_y(state.tcp.y());
  out->mutable_tcp()->set_z(state.tcp.z());
  out->set_final(final);
}

// How often a waiting worker looks at the run's cancel flag besides being woken (a shutdown
// sets it without a Wake): a timed sleep, not a spin.
constexpr std::chrono::milliseconds kCancelLook{250};

}  // namespace

ControlChannel::ControlChannel(int external, std::chrono::duration<double> timeout, bool hold_last,
                               const std::atomic<bool>* cancel)
    : external_(external),
      timeout_(timeout),
      hold_last_(hold_last),
      cancel_(cancel),
      command_(static_cast<size_t>(external), 0.0) {}

bool ControlChannel::Command(const ControlState& state, double* commands, RunStats* stats) {
  std::unique_lock<std::mutex> lock(mutex_);
  ToProto(state, false, &state_);
  published_ = state.step;
  awaited_ = state.step;
  changed_.notify_all();
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::duration_cast<std::chrono::steady_clock::duration>(timeout_);
  for (;;) {
    if (cancel_ != nullptr && cancel_->load()) {
      awaited_ = -1;
      stopped_ = true;
      StopCancelled(stats);
      return false;
    }
    if (!failure_.empty()) {
      awaited_ = -1;
      stopped_ = true;
      StopRun(stats, RunStatus::kFailed, failure_);
      return false;
    }
    if (detached_) {
      awaited_ = -1;
      stopped_ = true;
      StopRun(stats, RunStatus::kCancelled,
              FormatString("the controller's stream closed at t = %.9g s (step %ld) before the "
                           "run's end: the run is cancelled, its frames so far are kept",
                           state.t, state.step));
      return false;
    }
    if (awaited_ != state.step) {  // Deliver took the command
      for (int i = 0; i < external_; ++i) commands[i] = command_[static_cast<size_t>(i)];
      return true;
    }
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline) {
      const double seconds = timeout_.count();
      if (!attached_) {
        awaited_ = -1;
        stopped_ = true;
        StopRun(stats, RunStatus::kFailed,
                FormatString("no controller attached within control_timeout_s = %g s: open a "
                             "Control stream for this run (start.run_id) or start it with one",
                             seconds));
        return false;
      }
      if (hold_last_) {
        held_up_to_ = state.step;
        awaited_ = -1;
        for (int i = 0; i < external_; ++i) commands[i] = command_[static_cast<size_t>(i)];
        return true;
      }
      awaited_ = -1;
      stopped_ = true;
      StopRun(stats, RunStatus::kFailed,
              FormatString("the controller did not answer the state at t = %.9g s (step %ld) "
                           "within control_timeout_s = %g s: answer each state within it, "
                           "raise control_timeout_s, or set hold_last_command",
                           state.t, state.step, seconds));
      return false;
    }
    changed_.wait_until(lock, std::min(deadline, now + kCancelLook));
  }
}

void ControlChannel::Final(const ControlState& state) {
  std::lock_guard<std::mutex> lock(mutex_);
  ToProto(state, true, &state_);
  published_ = state.step;
  changed_.notify_all();
}

bool ControlChannel::Attach() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (attached_) return false;
  attached_ = true;
  changed_.notify_all();
  return true;
}

std::optional<v1::ControlState> ControlChannel::NextState(int64_t after,
                                                          std::chrono::duration<double> wait) {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait_for(lock, wait, [&] { return published_ > after || closed_; });
  if (published_ > after) return state_;
  return std::nullopt;
}

std::string ControlChannel::Deliver(int64_t step, const std::vector<double>& values) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (step == awaited_ && awaited_ >= 0) {
    command_ = values;
    last_taken_ = step;
    awaited_ = -1;
    changed_.notify_all();
    return "";
  }
  if (stopped_ || closed_) return "";  // the run stopped already: nothing to command
  if (step <= held_up_to_ && step > last_taken_) {
    return "";  // late for a step whose last command was held: dropped
  }
  std::string reason =
      awaited_ >= 0 ? FormatString(
                          "a command for step %ld, and the server waits for step %ld's: send "
                          "one command per state, naming the state's step",
                          static_cast<long>(step), static_cast<long>(awaited_))
                    : FormatString(
                          "a command for step %ld while no state awaits one (the last state "
                          "sent is step %ld's, answered already): send one command per state, "
                          "after it",
                          static_cast<long>(step), static_cast<long>(published_));
  failure_ = reason;
  changed_.notify_all();
  return reason;
}

void ControlChannel::Fail(const std::string& message) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (failure_.empty()) failure_ = message;
  changed_.notify_all();
}

void ControlChannel::Detach() {
  std::lock_guard<std::mutex> lock(mutex_);
  detached_ = true;
  changed_.notify_all();
}

void ControlChannel::Wake() {
  std::lock_guard<std::mutex> lock(mutex_);
  changed_.notify_all();
}

void ControlChannel::Close() {
  std::lock_guard<std::mutex> lock(mutex_);
  closed_ = true;
  changed_.notify_all();
}

bool ControlChannel::closed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return closed_;
}

}  // namespace mbstream

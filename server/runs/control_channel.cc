#include "server/runs/control_channel.h"

#include <algorithm>

#include "server/model/collision_geometry.h"
#include "server/sim/run_stop.h"
#include "shared/common/format.h"

namespace mbstream {

namespace {

void ToProto(const Vector3d& v, v1::Vector3* out) {
  out->set_x(v.x());
  out->set_y(v.y());
  out->set_z(v.z());
}

// The message's repeated fields are cleared and refilled: protobuf keeps the cleared
// elements and their strings' capacity, so a state of the same shape allocates nothing.
void ToProto(const ControlState& state, bool final, v1::ControlState* out) {
  out->set_step(state.step);
  out->set_t_s(state.t);
  out->mutable_q()->Assign(state.q->data(), state.q->data() + state.q->size());
  out->mutable_qd()->Assign(state.qd->data(), state.qd->data() + state.qd->size());
  out->mutable_tcp()->set_x(state.tcp.x());
  out->mutable_tcp()->set_y(state.tcp.y());
  out->mutable_tcp()->set_z(state.tcp.z());
  out->set_final(final);
  out->clear_sensors();
  if (state.sensors != nullptr) {
    for (const Vector3d& p : *state.sensors) ToProto(p, out->add_sensors());
  }
  out->clear_contacts();
  if (state.contacts != nullptr && state.model != nullptr) {
    const std::vector<CollisionGeometry>& g = state.model->collisions;
    for (const ContactPoint& c : *state.contacts) {
      v1::FrameContact* contact = out->add_contacts();
      const CollisionGeometry& a = g[static_cast<size_t>(c.geometry_a)];
      const CollisionGeometry& b = g[static_cast<size_t>(c.geometry_b)];
      contact->set_link_a(a.link);
      contact->set_collision_a(a.name);
      contact->set_link_b(b.link);
      contact->set_collision_b(b.name);
      ToProto(c.point, contact->mutable_point_m());
      ToProto(c.normal, contact->mutable_normal());
      contact->set_depth_m(c.depth);
      contact->set_normal_force_n(c.normal_force);
      ToProto(c.friction_force, contact->mutable_friction_force_n());
    }
  }
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

void ControlChannel::NotifyAll() {
  command_cv_.notify_all();
  stream_cv_.notify_all();
}

void ControlChannel::Send(std::unique_lock<std::mutex>& lock) {
  // The writer reads out_ outside the lock, and two threads send (the stream's SetWriter, the
  // worker): one Send at a time, or the second would rewrite out_ under the first's Write.
  stream_cv_.wait(lock, [&] { return !sending_; });
  if (writer_ == nullptr || written_ >= published_) return;
  written_ = published_;
  ++writer_calls_;
  sending_ = true;
  *out_.mutable_state() = state_;
  ControlWriter* writer = writer_;
  lock.unlock();
  const bool ok = writer->Write(out_);
  lock.lock();
  if (!ok) detached_ = true;
  sending_ = false;
  --writer_calls_;
  stream_cv_.notify_all();  // StopWriting, or a Send waiting for out_
}

bool ControlChannel::Command(const ControlState& state, double* commands, RunStats* stats) {
  std::unique_lock<std::mutex> lock(mutex_);
  ToProto(state, false, &state_);
  published_ = state.step;
  awaited_ = state.step;
  Send(lock);
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
    command_cv_.wait_until(lock, std::min(deadline, now + kCancelLook));
  }
}

void ControlChannel::Final(const ControlState& state) {
  std::unique_lock<std::mutex> lock(mutex_);
  ToProto(state, true, &state_);
  published_ = state.step;
  Send(lock);
}

bool ControlChannel::Attach() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (attached_) return false;
  attached_ = true;
  NotifyAll();
  return true;
}

void ControlChannel::SetWriter(ControlWriter* writer) {
  std::unique_lock<std::mutex> lock(mutex_);
  writer_ = writer;
  Send(lock);                           // the state published before the stream attached
  if (closed_ && writer_ != nullptr) {  // the run ended already
    ++writer_calls_;
    lock.unlock();
    writer->Ended();
    lock.lock();
    if (--writer_calls_ == 0 && stop_waits_) stream_cv_.notify_all();
  }
}

void ControlChannel::StopWriting() {
  std::unique_lock<std::mutex> lock(mutex_);
  writer_ = nullptr;
  stop_waits_ = true;
  stream_cv_.wait(lock, [&] { return writer_calls_ == 0; });
  stop_waits_ = false;
}

std::string ControlChannel::Deliver(int64_t step, const double* values, size_t count) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (step == awaited_ && awaited_ >= 0) {
    command_.assign(values, values + count);  // one per external joint (the stream checked)
    last_taken_ = step;
    awaited_ = -1;
    lock.unlock();
    command_cv_.notify_one();  // the worker, the one waiter (woken unlocked: no second wait)
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
  NotifyAll();
  return reason;
}

void ControlChannel::Fail(const std::string& message) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (failure_.empty()) failure_ = message;
  NotifyAll();
}

void ControlChannel::Detach() {
  std::lock_guard<std::mutex> lock(mutex_);
  detached_ = true;
  NotifyAll();
}

void ControlChannel::Wake() {
  std::lock_guard<std::mutex> lock(mutex_);
  NotifyAll();
}

void ControlChannel::Close() {
  std::unique_lock<std::mutex> lock(mutex_);
  closed_ = true;
  NotifyAll();
  if (writer_ == nullptr) return;  // SetWriter tells a stream attaching later
  ControlWriter* writer = writer_;
  ++writer_calls_;
  lock.unlock();
  writer->Ended();
  lock.lock();
  if (--writer_calls_ == 0 && stop_waits_) stream_cv_.notify_all();
}

bool ControlChannel::closed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return closed_;
}

}  // namespace mbstream

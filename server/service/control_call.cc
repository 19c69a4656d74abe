#include "server/service/control_call.h"

#include <spdlog/spdlog.h>

#include <cmath>
#include <vector>

#include "server/service/rpc_roles.h"
#include "server/service/status_from_exception.h"
#include "shared/common/format.h"

namespace mbstream {

namespace {

// |command| beyond this (N*m or N, rad or m, rad/s or m/s) is no command for a mechanism.
constexpr double kMaxCommand = 1e7;
// How often a call looks whether its run ended without its channel closing (a run cancelled
// while queued).
constexpr std::chrono::milliseconds kRunLook{250};

// The command's values checked: one per external joint, finite, |value| <= kMaxCommand.
std::string CheckCommand(const v1::ControlCommand& command,
                         const RunManager::ControlAttachment& attachment) {
  const int n = static_cast<int>(attachment.external_joints.size());
  if (command.values_size() != n) {
    std::string names;
    for (const std::string& name : attachment.external_joints) {
      names += (names.empty() ? "" : ", ") + name;
    }
    return FormatString(
        "command.values has %d entries and run %s has %d external joints (%s): give one "
        "value per external joint, in that order",
        command.values_size(), attachment.info.id().c_str(), n, names.c_str());
  }
  for (int i = 0; i < n; ++i) {
    const double value = command.values(i);
    const std::string& joint = attachment.external_joints[static_cast<size_t>(i)];
    if (!std::isfinite(value)) {
      return FormatString(
          "command.values[%d] (joint '%s') is %g, not a finite number: give "
          "finite commands",
          i, joint.c_str(), value);
    }
    if (std::abs(value) > kMaxCommand) {
      return FormatString(
          "command.values[%d] (joint '%s') is %g, beyond +-%g (%s): give a "
          "command a drive can deliver",
          i, joint.c_str(), value, kMaxCommand,
          attachment.commands[static_cast<size_t>(i)].c_str());
    }
  }
  return "";
}

}  // namespace

grpc::ServerBidiReactor<v1::ControlRequest, v1::ControlResponse>* ControlCall::Open(
    grpc::CallbackServerContext* context, const StreamDeps& deps) {
  auto call = std::make_shared<ControlCall>(context, deps);
  call->self_ = call;
  call->live_id_ = deps.live->Add(call);
  std::unique_lock<std::mutex> lock(call->mutex_);
  if (grpc::Status denied = deps.authorizer->Check(*context, RoleOf("Control")); !denied.ok()) {
    call->Conclude(denied);
  } else if (*deps.stopping) {
    call->Conclude(grpc::Status(grpc::StatusCode::UNAVAILABLE, "the server is stopping"));
  } else {
    call->read_wanted_ = true;  // the start
  }
  call->Drive(lock);
  return call.get();
}

ControlCall::ControlCall(grpc::CallbackServerContext* context, const StreamDeps& deps)
    : context_(context), deps_(deps) {}

void ControlCall::Conclude(const grpc::Status& status) {
  if (!conclusion_) conclusion_ = status;
}

void ControlCall::Poke() {
  if (!*deps_.stopping) return;
  std::unique_lock<std::mutex> lock(mutex_);
  Cancel(lock);
  Drive(lock);
}

void ControlCall::Cancel(std::unique_lock<std::mutex>& lock) {
  // Once Finish is posted the call may end and gRPC free its context: a TryCancel then took a
  // reference on a freed call (gRPC's "RefNonZero: prior > 0" abort at a server's stop, seen
  // under TSan). outside_ keeps Drive from finishing while this one is under way.
  if (finished_) return;
  ++outside_;
  lock.unlock();
  context_->TryCancel();
  lock.lock();
  --outside_;
}

void ControlCall::OnReadDone(bool ok) {
  std::unique_lock<std::mutex> lock(mutex_);
  reading_ = false;
  if (!ok) {
    reads_done_ = true;  // closed or gone: a run still going is cancelled
    if (channel_ != nullptr) {
      channel_->Detach();
    } else if (!starting_) {
      Conclude(
          grpc::Status(grpc::StatusCode::CANCELLED, "the Control stream closed before its start"));
    }
    Drive(lock);
    return;
  }
  if (!start_read_) {
    start_read_ = true;
    if (!request_.has_start()) {
      Conclude(grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                            "the first message of a Control stream is `start` (model and spec, "
                            "or run_id); then one `command` per state"));
      Drive(lock);
      return;
    }
    starting_ = true;
    starter_ = std::thread([this] { Start(); });  // joined in OnDone
    return;
  }
  lock.unlock();
  HandleCommand();  // request_, attachment_ and channel_ are the reader's alone now
  lock.lock();
  Drive(lock);
}

void ControlCall::HandleCommand() {
  std::string refused;
  grpc::StatusCode code = grpc::StatusCode::INVALID_ARGUMENT;
  if (!request_.has_command()) {
    refused = "after start, a Control stream sends only commands (one per state)";
  } else if (const v1::ControlCommand& command = request_.command();
             !command.run_id().empty() && command.run_id() != run_id_) {
    code = grpc::StatusCode::PERMISSION_DENIED;
    refused = "this stream controls run " + run_id_ + "; a command for run " +
              command.run_id().substr(0, 64) + " is refused: a stream commands its own run";
  } else {
    refused = CheckCommand(command, attachment_);
    if (refused.empty()) {
      refused = channel_->Deliver(command.step(), command.values().data(),
                                  static_cast<size_t>(command.values_size()));
      std::lock_guard<std::mutex> lock(mutex_);
      if (refused.empty()) {
        read_wanted_ = true;
      } else {  // the channel failed the run already
        Conclude(grpc::Status(code, refused));
      }
      return;
    }
  }
  channel_->Fail("the controller's command was refused: " + refused);
  std::lock_guard<std::mutex> lock(mutex_);
  Conclude(grpc::Status(code, refused));
}

void ControlCall::Start() {
  const grpc::Status status = Serve([&] { return Attach(); });
  std::unique_lock<std::mutex> lock(mutex_);
  starting_ = false;
  if (!status.ok()) Conclude(status);
  Drive(lock);
}

grpc::Status ControlCall::Attach() {
  RunManager& runs = *deps_.runs;
  if (runs.replica().shared_store()) {
    return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION,
                        "a controlled run integrates on the server its stream reaches, and this "
                        "server shares its store with a cluster (any replica may claim a run): "
                        "control runs on a server with its own store (--data)");
  }
  const v1::ControlStart& start = request_.start();
  const std::string caller = deps_.authorizer->CallerId(*context_);
  std::string run_id = start.run_id();
  if (!start.model().empty() || start.has_spec()) {
    if (!run_id.empty()) {
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                          "start gives both a new run (model, spec) and run_id: give one of them");
    }
    bool external = false;
    for (const v1::Drive& drive : start.spec().drives()) external |= drive.has_external();
    if (!external) {
      return grpc::Status(
          grpc::StatusCode::INVALID_ARGUMENT,
          "start.spec has no external drive, so there is nothing to control: give "
          "drives {\"external\": {\"command\": \"effort\", \"period_s\": 0.001}} on "
          "the joints your controller commands");
    }
    run_id = runs.Start(start.model(), start.spec(), caller).id();
  } else if (run_id.empty()) {
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                        "start is empty: give model and spec (a new run) or run_id (a run "
                        "started with external drives)");
  }
  RunManager::ControlAttachment attachment =
      runs.AttachControl(run_id, caller, deps_.authorizer->CallerHas(*context_, Role::kAdmin));
  if (attachment.channel == nullptr) {
    return grpc::Status(grpc::StatusCode::PERMISSION_DENIED, attachment.denied);
  }
  v1::ControlResponse response;
  v1::ControlStarted* started = response.mutable_started();
  *started->mutable_run() = attachment.info;
  for (const std::string& name : attachment.joint_names) {
    started->add_joint_names(name);
    started->add_velocity_names(name);
  }
  for (const std::string& name : attachment.position_names) started->add_position_names(name);
  for (const std::string& name : attachment.external_joints) started->add_external_joints(name);
  for (const std::string& command : attachment.commands) started->add_commands(command);
  started->set_period_s(attachment.period_s);
  for (const std::string& name : attachment.sensor_names) started->add_sensor_names(name);
  const std::shared_ptr<ControlChannel> channel = attachment.channel;
  bool gone = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    run_id_ = run_id;
    attachment_ = std::move(attachment);
    channel_ = channel;
    gone = broken_ || finished_ || reads_done_;
    if (!gone) {
      queue_.push_back(std::move(response));  // before any state
      read_wanted_ = true;                    // the commands
    }
  }
  if (gone) {
    channel->Detach();  // the client went away during the start: the run is cancelled
    return grpc::Status(grpc::StatusCode::CANCELLED, "the controller went away");
  }
  channel->SetWriter(this);  // the state published before, if any, and Ended if it ended
  std::weak_ptr<ControlCall> weak = weak_from_this();
  deps_.pump->PostAt(std::chrono::steady_clock::now() + kRunLook, [weak] {
    if (std::shared_ptr<ControlCall> call = weak.lock()) call->WatchRun();
  });
  return grpc::Status::OK;
}

void ControlCall::WatchRun() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (finished_ || ended_queued_) return;
  }
  if (!deps_.runs->replays().IsActive(run_id_)) {
    Ended();
    return;
  }
  std::weak_ptr<ControlCall> weak = weak_from_this();
  deps_.pump->PostAt(std::chrono::steady_clock::now() + kRunLook, [weak] {
    if (std::shared_ptr<ControlCall> call = weak.lock()) call->WatchRun();
  });
}

bool ControlCall::Write(const v1::ControlResponse& response) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (finished_ || broken_) return false;
  if (queue_.size() >= kMaxQueued) {  // the client does not read
    broken_ = true;
    Cancel(lock);
    Drive(lock);
    return false;
  }
  queue_.push_back(response);
  Drive(lock);
  return true;
}

void ControlCall::Ended() {
  v1::ControlResponse response;
  bool ok = true;
  try {
    *response.mutable_ended() = deps_.runs->Get(run_id_);
  } catch (const std::exception& error) {  // the store failing Get: the stream ends
    spdlog::error("Control stream of run {}: {}", run_id_, error.what());
    ok = false;
  }
  std::unique_lock<std::mutex> lock(mutex_);
  if (ended_queued_) return;
  ended_queued_ = true;
  if (ok) {
    queue_.push_back(std::move(response));
  } else {
    Conclude(grpc::Status(grpc::StatusCode::INTERNAL, "the run's final info could not be read"));
  }
  Drive(lock);
}

void ControlCall::OnWriteDone(bool ok) {
  std::unique_lock<std::mutex> lock(mutex_);
  writing_ = false;
  queue_.pop_front();
  if (!ok && !broken_) {
    broken_ = true;
    if (channel_ != nullptr) channel_->Detach();
    lock.unlock();
    context_->TryCancel();  // the read in flight ends too
    lock.lock();
  }
  Drive(lock);
}

void ControlCall::OnCancel() {
  std::unique_lock<std::mutex> lock(mutex_);
  broken_ = true;
  Conclude(grpc::Status(grpc::StatusCode::CANCELLED, "the Control stream was cancelled"));
  if (channel_ != nullptr) channel_->Detach();
  Drive(lock);
}

void ControlCall::Drive(std::unique_lock<std::mutex>& lock) {
  const auto outside = [&](auto start) {
    ++outside_;
    lock.unlock();
    start();
    lock.lock();
    --outside_;
  };
  for (;;) {
    if (finished_) return;
    if (!writing_ && !queue_.empty() && !broken_) {
      writing_ = true;
      const v1::ControlResponse* next = &queue_.front();  // stays put until OnWriteDone
      outside([&] { StartWrite(next); });
      continue;
    }
    if (read_wanted_ && !reading_ && !reads_done_ && !broken_ && !conclusion_) {
      read_wanted_ = false;
      reading_ = true;
      outside([&] { StartRead(&request_); });
      continue;
    }
    break;
  }
  if (outside_ > 0 || writing_ || reading_ || starting_) return;
  // What the stream still owes: the run's end, once a run is attached.
  const bool end_sent = channel_ == nullptr || (ended_queued_ && queue_.empty());
  grpc::Status status;
  if (broken_) {
    status = conclusion_.value_or(grpc::Status(grpc::StatusCode::CANCELLED, "the client is gone"));
  } else if (conclusion_ && end_sent) {
    status = *conclusion_;
  } else if (reads_done_ && end_sent) {
    status = grpc::Status::OK;
  } else {
    return;
  }
  finished_ = true;
  // On the pump, never here: gRPC may run OnDone inside Finish, and this thread may be the
  // starter (which OnDone joins) or the worker inside a channel call (which OnDone waits for).
  // The caller touches nothing of the call after Drive.
  std::shared_ptr<ControlCall> self = shared_from_this();
  lock.unlock();
  deps_.pump->Post([self, status] { self->Finish(status); });
}

void ControlCall::OnDone() {
  if (starter_.joinable()) starter_.join();
  if (channel_ != nullptr) channel_->StopWriting();
  deps_.live->Remove(live_id_);
  std::shared_ptr<ControlCall> self = std::move(self_);  // may be the last hold
}

}  // namespace mbstream

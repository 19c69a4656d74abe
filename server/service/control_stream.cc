// Simulation.Control (proto/mbstream/v1/control.proto): a controller in the loop of a run,
// lockstep. The handler's thread reads the commands and hands them to the run's
// ControlChannel (server/runs/control_channel.h); a writer thread of the stream sends each
// state the worker publishes there, then the run's end.
#include <spdlog/spdlog.h>

#include <atomic>
#include <cmath>
#include <optional>
#include <thread>
#include <vector>

#include "server/service/simulation_service.h"
#include "shared/common/format.h"

namespace mbstream {

namespace {

// |command| beyond this (N*m or N, rad or m, rad/s or m/s) is no command for a mechanism.
constexpr double kMaxCommand = 1e7;
// How often the writer looks whether the run ended without its channel closing (a run
// cancelled while queued) or the reader finished.
constexpr std::chrono::milliseconds kWriterLook{250};

grpc::Status Refused(grpc::StatusCode code, const std::string& message) {
  return grpc::Status(code, message);
}

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

grpc::Status SimulationService::Control(
    grpc::ServerContext* context,
    grpc::ServerReaderWriter<v1::ControlResponse, v1::ControlRequest>* stream) {
  return Admit(*context, "Control",
               [&]() -> grpc::Status { return ServeControl(*context, *stream); });
}

grpc::Status SimulationService::ServeControl(
    grpc::ServerContext& context,
    grpc::ServerReaderWriter<v1::ControlResponse, v1::ControlRequest>& stream) {
  v1::ControlRequest request;
  if (!stream.Read(&request)) {
    return Refused(grpc::StatusCode::CANCELLED, "the Control stream closed before its start");
  }
  if (!request.has_start()) {
    return Refused(grpc::StatusCode::INVALID_ARGUMENT,
                   "the first message of a Control stream is `start` (model and spec, or "
                   "run_id); then one `command` per state");
  }
  if (runs_->replica().shared_store()) {
    return Refused(grpc::StatusCode::FAILED_PRECONDITION,
                   "a controlled run integrates on the server its stream reaches, and this "
                   "server shares its store with a cluster (any replica may claim a run): "
                   "control runs on a server with its own store (--data)");
  }
  const v1::ControlStart& start = request.start();
  const std::string caller = authorizer_->CallerId(context);
  std::string run_id = start.run_id();
  if (!start.model().empty() || start.has_spec()) {
    if (!run_id.empty()) {
      return Refused(grpc::StatusCode::INVALID_ARGUMENT,
                     "start gives both a new run (model, spec) and run_id: give one of them");
    }
    bool external = false;
    for (const v1::Drive& drive : start.spec().drives()) external |= drive.has_external();
    if (!external) {
      return Refused(grpc::StatusCode::INVALID_ARGUMENT,
                     "start.spec has no external drive, so there is nothing to control: give "
                     "drives {\"external\": {\"command\": \"effort\", \"period_s\": 0.001}} on "
                     "the joints your controller commands");
    }
    run_id = runs_->Start(start.model(), start.spec(), caller).id();
  } else if (run_id.empty()) {
    return Refused(grpc::StatusCode::INVALID_ARGUMENT,
                   "start is empty: give model and spec (a new run) or run_id (a run started "
                   "with external drives)");
  }
  const RunManager::ControlAttachment attachment =
      runs_->AttachControl(run_id, caller, authorizer_->CallerHas(context, Role::kAdmin));
  if (attachment.channel == nullptr) {
    return Refused(grpc::StatusCode::PERMISSION_DENIED, attachment.denied);
  }
  ControlChannel& channel = *attachment.channel;
  {
    v1::ControlResponse response;
    v1::ControlStarted* started = response.mutable_started();
    *started->mutable_run() = attachment.info;
    for (const std::string& name : attachment.joint_names) started->add_joint_names(name);
    for (const std::string& name : attachment.external_joints) started->add_external_joints(name);
    for (const std::string& command : attachment.commands) started->add_commands(command);
    started->set_period_s(attachment.period_s);
    if (!stream.Write(response)) {
      channel.Detach();
      return Refused(grpc::StatusCode::CANCELLED, "the controller went away");
    }
  }

  std::atomic<bool> reading{true};
  std::thread writer([&] {
    try {
      WriteStates(channel, run_id, reading, context, stream);
    } catch (const std::exception& error) {  // the store failing Get: the stream ends
      spdlog::error("Control stream of run {}: {}", run_id, error.what());
      channel.Detach();
    }
  });
  grpc::Status status = ReadCommands(channel, attachment, run_id, stream);
  if (status.ok()) channel.Detach();  // closed or gone: a run still going is cancelled
  reading = false;
  writer.join();
  return status;
}

void SimulationService::WriteStates(
    ControlChannel& channel, const std::string& run_id, const std::atomic<bool>& reading,
    grpc::ServerContext& context,
    grpc::ServerReaderWriter<v1::ControlResponse, v1::ControlRequest>& stream) {
  {
    v1::ControlResponse response;
    int64_t sent = -1;
    for (;;) {
      if (std::optional<v1::ControlState> state = channel.NextState(sent, kWriterLook)) {
        sent = state->step();
        *response.mutable_state() = std::move(*state);
        if (!stream.Write(response)) {
          channel.Detach();
          return;
        }
        continue;
      }
      if (channel.closed() || !runs_->replays().IsActive(run_id)) {
        *response.mutable_ended() = runs_->Get(run_id);
        stream.Write(response);
        return;
      }
      if (!reading && stopping_) return;
      if (!reading && context.IsCancelled()) return;
    }
  }
}

grpc::Status SimulationService::ReadCommands(
    ControlChannel& channel, const RunManager::ControlAttachment& attachment,
    const std::string& run_id,
    grpc::ServerReaderWriter<v1::ControlResponse, v1::ControlRequest>& stream) {
  v1::ControlRequest request;
  grpc::Status status = grpc::Status::OK;
  while (stream.Read(&request)) {
    std::string refused;
    grpc::StatusCode code = grpc::StatusCode::INVALID_ARGUMENT;
    if (!request.has_command()) {
      refused = "after start, a Control stream sends only commands (one per state)";
    } else if (const v1::ControlCommand& command = request.command();
               !command.run_id().empty() && command.run_id() != run_id) {
      code = grpc::StatusCode::PERMISSION_DENIED;
      refused = "this stream controls run " + run_id + "; a command for run " +
                command.run_id().substr(0, 64) + " is refused: a stream commands its own run";
    } else {
      refused = CheckCommand(command, attachment);
      if (refused.empty()) {
        refused = channel.Deliver(
            command.step(), std::vector<double>(command.values().begin(), command.values().end()));
        if (!refused.empty()) {  // the channel failed the run already
          status = Refused(code, refused);
          break;
        }
        continue;
      }
    }
    channel.Fail("the controller's command was refused: " + refused);
    status = Refused(code, refused);
    break;
  }
  return status;
}

}  // namespace mbstream

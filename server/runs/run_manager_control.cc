// RunManager's side of the Control stream (issue 45): a stream attaches to a run with
// external drives (control_channel.h).
#include "server/model/coordinate_names.h"
#include "server/runs/request_error.h"
#include "server/runs/run_manager.h"
#include "server/wire/stats_conversion.h"

namespace mbstream {

RunManager::ControlAttachment RunManager::AttachControl(const std::string& run_id,
                                                        const std::string& caller, bool admin) {
  ControlAttachment attachment;
  const std::shared_ptr<Run> run = FindActive(run_id);
  if (run == nullptr) {
    const v1::RunInfo info = Get(run_id);  // NOT_FOUND first
    throw RequestError(
        RequestErrorKind::kFailedPrecondition,
        "run " + run_id + " is " + v1::RunState_Name(info.state()) +
            (IsFinalState(info.state())
                 ? ": a controller attaches to a queued or running run"
                 : " on replica " + info.replica() + ": attach to it on that server (" +
                       info.replica_address() + ")"));
  }
  attachment.info = run->Info();
  if (run->control() == nullptr) {
    throw RequestError(RequestErrorKind::kFailedPrecondition,
                       "run " + run_id +
                           " has no external drives: nothing to control; start a run whose "
                           "spec gives drives {\"external\": {...}}");
  }
  const std::string& owner = attachment.info.owner();
  if (!owner.empty() && owner != caller && !admin) {
    attachment.denied = "run " + run_id +
                        " was started with another token; only that token or an admin token "
                        "may control it";
    return attachment;
  }
  if (!run->control()->Attach()) {
    attachment.denied = "run " + run_id + " is controlled by another stream already";
    return attachment;
  }
  attachment.channel = run->control();
  run->UpdateInfo([&](v1::RunInfo& info) {
    info.set_controller(caller.empty() ? "a Control stream" : caller);
  });
  attachment.info = run->Info();
  const Model& model = run->model().model;
  const RunConfig& config = run->config();
  attachment.position_names = PositionNames(model);
  attachment.joint_names = VelocityNames(model);
  for (int i = 0; i < model.num_dofs(); ++i) {
    const std::string& name = attachment.joint_names[static_cast<size_t>(i)];
    const DriveConfig& drive = config.drives[static_cast<size_t>(i)];
    if (drive.kind != DriveConfig::Kind::kExternal) continue;
    attachment.external_joints.push_back(name);
    attachment.commands.push_back(drive.command == DriveConfig::Command::kEffort     ? "effort"
                                  : drive.command == DriveConfig::Command::kPosition ? "position"
                                                                                     : "velocity");
    attachment.period_s = drive.period;
  }
  for (const SensorPointConfig& sensor : config.sensor_points) {
    attachment.sensor_names.push_back(sensor.name);
  }
  return attachment;
}

}  // namespace mbstream

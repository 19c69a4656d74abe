// A controller in the loop of a run: at each control instant t_k = k h of a run with
// external drives (DriveConfig::Kind::kExternal) the engine hands it the state and takes the
// commands it holds over [t_k, t_k+1) (zero-order hold). The server's Control stream is one
// (server/runs/control_channel.h); a test's own law is another. The engine knows nothing of
// where the commands come from.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "server/contact/contact_point.h"
#include "server/math/spatial.h"
#include "server/model/model.h"
#include "server/sim/run_result.h"

namespace mbstream {

// The state at a control instant (no free bodies: q and qd have one value per joint).
struct ControlState {
  long step = 0;                        // k: t = k h
  double t = 0.0;                       // s
  const Eigen::VectorXd* q = nullptr;   // rad or m, in the model's joint order
  const Eigen::VectorXd* qd = nullptr;  // rad/s or m/s
  Vector3d tcp = Vector3d::Zero();      // m, the TCP's position in the base frame (0: none)
  // m, the world (base) frame: each RunConfig::sensor_points' position, in its order.
  const std::vector<Vector3d>* sensors = nullptr;
  // The active contacts at t (a run with contact; null without), world frame: their geometry
  // indices are into model->collisions.
  const std::vector<ContactPoint>* contacts = nullptr;
  const Model* model = nullptr;  // the run's
};

class ControlLaw {
 public:
  virtual ~ControlLaw() = default;

  // At control instant state.step: fills `commands`, one per external joint in joint order
  // (DriveSet::external_joints), each in its drive's command unit. Returns false to stop the
  // run, with the status and message in `stats` (StopRun, StopCancelled).
  virtual bool Command(const ControlState& state, double* commands, RunStats* stats) = 0;

  // The run reached its end (duration_s): its final state, for which no command is asked.
  virtual void Final(const ControlState& /*state*/) {}
};

}  // namespace mbstream

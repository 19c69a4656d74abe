// The drives of a run, joint by joint: reference motions and applied efforts.
#pragma once

#include <vector>

#include "server/model/model.h"
#include "server/sim/run_config.h"
#include "server/sim/trajectory.h"

namespace mbstream {

class DriveSet {
 public:
  // config.drives has one entry per joint (server/spec guarantees it; checked).
  DriveSet(const Model& model, const RunConfig& config);

  int size() const { return static_cast<int>(drives_.size()); }
  DriveConfig::Kind kind(int joint) const { return drives_[joint].kind; }
  bool prescribed(int joint) const { return kind(joint) == DriveConfig::Kind::kPrescribed; }
  // Prescribed by velocity (q integrated from qd_ref), the seed's drive.
  bool velocity_source(int joint) const {
    return prescribed(joint) && drives_[joint].velocity_source;
  }
  int num_prescribed() const { return num_prescribed_; }
  bool all_prescribed() const { return num_prescribed_ == size(); }
  // True when some drive or damping does work (energy is then not conserved).
  bool any_work() const { return any_work_; }

  // Reference motion of a prescribed or servo joint at time t (s).
  TrajectoryPoint Reference(int joint, double t) const { return references_[joint].At(t); }

  // Effort of the actuator of a non-prescribed joint at (t, q, qd): the torque law or the
  // servo law, zero for passive joints (N*m or N). Damping is not included.
  double ActuatorEffort(int joint, double t, double q, double qd) const;

  // The joint's viscous damping coefficient (N*m*s/rad or N*s/m).
  double damping(int joint) const { return damping_[joint]; }

 private:
  std::vector<DriveConfig> drives_;
  std::vector<TrajectoryEvaluator> references_;
  std::vector<double> damping_;
  int num_prescribed_ = 0;
  bool any_work_ = false;
};

}  // namespace mbstream

#include "server/sim/drive_set.h"

#include <cmath>

#include "server/common/check.h"

namespace mbstream {

DriveSet::DriveSet(const Model& model, const RunConfig& config) : drives_(config.drives) {
  MBSTREAM_CHECK_MSG(static_cast<int>(drives_.size()) == model.num_dofs(),
                     "RunConfig must have one drive per joint");
  references_.resize(drives_.size());
  for (size_t i = 0; i < drives_.size(); ++i) {
    const DriveConfig& drive = drives_[i];
    const double damping = model.bodies[i].joint.damping;
    damping_.push_back(damping);
    if (drive.kind == DriveConfig::Kind::kPrescribed || drive.kind == DriveConfig::Kind::kPdServo) {
      references_[i] = TrajectoryEvaluator(drive.trajectory);
    }
    if (drive.kind == DriveConfig::Kind::kPrescribed) ++num_prescribed_;
    if (drive.kind != DriveConfig::Kind::kPassive || damping > 0.0) any_work_ = true;
  }
}

double DriveSet::ActuatorEffort(int joint, double t, double q, double qd) const {
  const DriveConfig& drive = drives_[joint];
  switch (drive.kind) {
    case DriveConfig::Kind::kTorque:
      return drive.constant + drive.amplitude * std::sin(drive.omega * t + drive.phase);
    case DriveConfig::Kind::kPdServo: {
      const TrajectoryPoint ref = references_[joint].At(t);
      return drive.kp * (ref.q - q) + drive.kd * (ref.qd - qd);
    }
    case DriveConfig::Kind::kPassive:
    case DriveConfig::Kind::kPrescribed:
      return 0.0;
  }
  return 0.0;
}

}  // namespace mbstream

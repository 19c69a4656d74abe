// A run's initial joint state.
#pragma once

#include <Eigen/Core>

#include "server/drives/drive_set.h"
#include "server/sim/run_config.h"

namespace mbstream {

// y0 = [q0; qd0] (2n): the spec's values, prescribed joints on their track (a velocity
// source keeps the spec's q0 when it gives one).
Eigen::VectorXd InitialJointState(const RunConfig& config, const DriveSet& drives, int n);

}  // namespace mbstream

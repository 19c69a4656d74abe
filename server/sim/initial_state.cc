#include "server/sim/initial_state.h"

namespace mbstream {

Eigen::VectorXd InitialJointState(const RunConfig& config, const DriveSet& drives, int n) {
  Eigen::VectorXd y = Eigen::VectorXd::Zero(2 * n);
  if (config.q0.size() == n) y.head(n) = config.q0;
  if (config.qd0.size() == n) y.tail(n) = config.qd0;
  for (int i = 0; i < n; ++i) {
    if (!drives.prescribed(i)) continue;
    const TrajectoryPoint ref = drives.Reference(i, 0.0);
    if (!drives.velocity_source(i) || config.q0.size() != n) y(i) = ref.q;
    y(n + i) = ref.qd;
  }
  return y;
}

}  // namespace mbstream

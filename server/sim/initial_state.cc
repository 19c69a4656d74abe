#include "server/sim/initial_state.h"

#include "server/kinematics/quaternion.h"
#include "shared/common/check.h"

namespace mbstream {

Eigen::VectorXd InitialJointState(const RunConfig& config, const DriveSet& drives, int n) {
  MBSTREAM_CHECK_MSG(config.initial_bodies.empty(),
                     "initial_bodies need a model with free bodies: ValidateRun first");
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

Eigen::VectorXd InitialJointState(const RunConfig& config, const DriveSet& drives,
                                  const Model& model) {
  if (!model.has_quaternions()) return InitialJointState(config, drives, model.nv());
  const int nq = model.nq(), nv = model.nv();
  Eigen::VectorXd y = Eigen::VectorXd::Zero(nq + nv);
  if (config.q0.size() == nq) {
    y.head(nq) = config.q0;
  } else {
    NeutralPositions(model, y.data());
  }
  if (config.qd0.size() == nv) y.tail(nv) = config.qd0;
  ApplyInitialBodies(model, config.initial_bodies, y.data(), y.data() + nq);
  for (const int k : model.quaternions) quaternion::Normalise(y.data() + k);
  for (const Body& body : model.bodies) {
    if (body.nv() != 1) continue;  // a free or ball joint: never prescribed
    const int i = body.v_index;
    if (!drives.prescribed(i)) continue;
    const TrajectoryPoint ref = drives.Reference(i, 0.0);
    if (!drives.velocity_source(i) || config.q0.size() != nq) y(body.q_index) = ref.q;
    y(nq + i) = ref.qd;
  }
  return y;
}

}  // namespace mbstream

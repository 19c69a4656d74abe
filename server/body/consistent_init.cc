#include "server/body/consistent_init.h"

#include <algorithm>

#include "server/body/quaternion.h"
#include "server/dynamics/rnea.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/model/data.h"

namespace mbstream {

Eigen::VectorXd BodyStateFromJoints(const Model& model, const BodyModel& bm,
                                    const Eigen::VectorXd& q0, const Eigen::VectorXd& qd0) {
  Data data(model);
  ForwardKinematics(model, data, q0);
  Rnea(model, data, q0, qd0, data.zeros);  // fills data.v: [w; v_origin] in body axes
  Eigen::VectorXd y = Eigen::VectorXd::Zero(bm.dae_size());
  for (int i = 0; i < bm.n; ++i) {
    const Pose& X = data.X_world[i];
    const Vector3d w = data.v[i].head<3>();
    const Vector3d v_origin = data.v[i].tail<3>();
    y.segment<3>(BodyModel::position(i)) = X.Apply(bm.com[i]);
    y.segment<4>(BodyModel::quaternion(i)) = QuaternionFromRotation(X.R);
    y.segment<3>(bm.velocity(i)) = X.R * (v_origin + w.cross(bm.com[i]));
    y.segment<3>(bm.omega(i)) = w;
  }
  return y;
}

bool ConsistentInitialState(const Model& model, const BodyModel& bm, BodyMechanics& mechanics,
                            double t0, const Eigen::VectorXd& q0, const Eigen::VectorXd& qd0,
                            BodyInitialState* state) {
  const int n = bm.n;
  state->y = BodyStateFromJoints(model, bm, q0, qd0);
  state->yp = Eigen::VectorXd::Zero(bm.dae_size());
  Eigen::VectorXd& y = state->y;
  mechanics.Load(t0, y.data());
  mechanics.EvaluateConstraints(/*acceleration_terms=*/true);
  mechanics.EvaluateForces();
  if (!mechanics.SolveAccelerations(0.0, 0.0)) return false;
  for (int i = 0; i < n; ++i) {
    state->yp.segment<3>(BodyModel::position(i)) = mechanics.v(i);
    state->yp.segment<4>(BodyModel::quaternion(i)) = QuaternionRate(mechanics.e(i), mechanics.w(i));
  }
  state->yp.segment(7 * n, 6 * n) = mechanics.nu_dot();
  y.tail(bm.m) = mechanics.lambda();
  const Eigen::VectorXd velocity_residual = mechanics.G() * mechanics.nu() + mechanics.g_t();
  state->constraint_residual = std::max(bm.m > 0 ? mechanics.g().cwiseAbs().maxCoeff() : 0.0,
                                        bm.m > 0 ? velocity_residual.cwiseAbs().maxCoeff() : 0.0);
  return true;
}

}  // namespace mbstream

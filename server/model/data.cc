#include "server/model/data.h"

namespace mbstream {

Data::Data(const Model& model) {
  const size_t n = model.bodies.size();
  X_parent.resize(n);
  X_world.resize(n);
  frame_world.resize(model.frames.size());
  v.assign(n, Vector6d::Zero());
  a.assign(n, Vector6d::Zero());
  f.assign(n, Vector6d::Zero());
  c.assign(n, Vector6d::Zero());
  S.assign(n, Vector6d::Zero());
  I.resize(n);
  IA.assign(n, Matrix6d::Zero());
  pA.assign(n, Vector6d::Zero());
  U.assign(n, Vector6d::Zero());
  S_index.assign(n, -1);
  D.assign(n, 0.0);
  inv_D.assign(n, 0.0);
  u.assign(n, 0.0);
  if (model.has_ball_joints()) {
    U3.assign(n, Matrix63d::Zero());
    D3_inv.assign(n, Matrix3d::Zero());
    u3.assign(n, Vector3d::Zero());
  }
  for (size_t i = 0; i < n; ++i) {
    I[i] = model.bodies[i].inertia.ToMatrix();
    const Joint& joint = model.bodies[i].joint;
    if (joint.type == JointType::kFree || joint.type == JointType::kBall) {
      continue;  // six or three columns (server/kinematics/free_joint.h, ball_joint.h); S stays 0
    }
    if (joint.type == JointType::kRevolute) {
      S[i].head<3>() = joint.axis;
    } else {
      S[i].tail<3>() = joint.axis;
    }
    for (int k = 0; k < 6; ++k) {
      if (S[i] == Vector6d::Unit(k)) S_index[i] = k;
    }
  }
  const auto dofs = static_cast<Eigen::Index>(model.nv());
  zeros = Eigen::VectorXd::Zero(dofs);
  tau = Eigen::VectorXd::Zero(dofs);
  qdd = Eigen::VectorXd::Zero(dofs);
  gravity_torque = Eigen::VectorXd::Zero(dofs);
  M = Eigen::MatrixXd::Zero(dofs, dofs);
  J = Eigen::MatrixXd::Zero(6, dofs);
}

}  // namespace mbstream

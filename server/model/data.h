// The per-run workspace of the physics algorithms: allocated once for a Model, reused by
// every call, so that no algorithm allocates in a time step.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "server/model/model.h"

namespace mbstream {

struct Data {
  explicit Data(const Model& model);

  // Kinematics (ForwardKinematics).
  std::vector<Pose> X_parent;     // X_PB: body in its parent body (or the base)
  std::vector<Pose> X_world;      // X_WB: body in the base (world) frame
  std::vector<Pose> frame_world;  // X_WF for every Model::frames entry

  // Per-body spatial quantities, in the body's own frame (see server/math/spatial.h).
  std::vector<Vector6d> v;    // spatial velocity
  std::vector<Vector6d> a;    // spatial acceleration (gravity included as a base accel.)
  std::vector<Vector6d> f;    // force transmitted by the body's joint
  std::vector<Vector6d> c;    // velocity-product acceleration v x S qd
  std::vector<Vector6d> S;    // joint motion subspace (axis), constant; 0 for a free or ball joint
  std::vector<int> S_index;   // k when S is the unit vector e_k (a coordinate axis), else -1
  std::vector<Matrix6d> I;    // body spatial inertia about its origin, constant
  std::vector<Matrix6d> IA;   // articulated-body (ABA) or composite (CRBA) inertia
  std::vector<Vector6d> pA;   // articulated bias force
  std::vector<Vector6d> U;    // IA S
  std::vector<double> D;      // S^T IA S + armature
  std::vector<double> inv_D;  // 1 / D (ABA's pass 3 for an axis joint multiplies by it)
  std::vector<double> u;      // tau - S^T pA
  // A ball joint's ABA terms (S = [I3; 0]; server/kinematics/ball_joint.h), one per body (only
  // ball joints' entries are used; empty without ball joints):
  std::vector<Matrix63d> U3;     // IA S: IA's first three columns
  std::vector<Matrix3d> D3_inv;  // (S^T IA S)^-1
  std::vector<Vector3d> u3;      // tau - S^T pA

  // Per velocity coordinate (nv; num_dofs):
  Eigen::VectorXd zeros;  // zeros, for calls with qd = 0 or qdd = 0

  // Results.
  Eigen::VectorXd tau;             // Rnea: joint forces (N*m or N)
  Eigen::VectorXd qdd;             // Aba: joint accelerations (rad/s^2 or m/s^2)
  Eigen::VectorXd gravity_torque;  // GravityVector: g(q)
  Eigen::MatrixXd M;               // Crba: joint-space mass matrix, symmetric (both halves)
  Eigen::MatrixXd J;               // PointJacobian scratch/result, 6 x nv
};

}  // namespace mbstream

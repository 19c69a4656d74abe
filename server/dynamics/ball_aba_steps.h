// The articulated-body algorithm's passes 2 and 3 for a ball joint (Featherstone, RBDA 7.3 with
// a three-column motion subspace S = [I3; 0]: server/kinematics/ball_joint.h). Pass 1 is the
// general one (the joint's pose, v = X v_parent + [w; 0], c = v x [w; 0], IA = I, pA = v x* I v).
// Shared by Aba (free_aba.cc) and HybridAba (free_tree.cc). Internal to server/dynamics.
// Allocates nothing.
#pragma once

#include <Eigen/Cholesky>

#include "server/model/data.h"
#include "server/model/model.h"
#include "shared/common/check.h"

namespace mbstream::ball_aba {

// Pass 2 for body i on a ball joint with generalised forces tau (3 values): U = IA S (IA's
// first three columns), D = S^T IA S, u = tau - S^T pA; Ia = IA - U D^-1 U^T and
// pa = pA + Ia c + U D^-1 u added to the parent's. IA may hold only its upper triangle (the
// axis kernels' children add only those, aba_passes.h): it is made whole first.
inline void BackwardStep(const Body& body, int i, const double* tau, Data& data) {
  Matrix6d& IA = data.IA[i];
  for (int q = 0; q < 6; ++q) {
    for (int r = q + 1; r < 6; ++r) IA(r, q) = IA(q, r);
  }
  Matrix63d& U = data.U3[i];
  U = IA.leftCols<3>();
  const Eigen::LLT<Matrix3d> llt(U.topRows<3>());
  MBSTREAM_CHECK_MSG(llt.info() == Eigen::Success,
                     "articulated inertia of a ball joint is not positive definite");
  data.D3_inv[i] = llt.solve(Matrix3d::Identity());
  data.u3[i] = Vector3d(tau[0], tau[1], tau[2]) - data.pA[i].head<3>();
  if (body.parent == kBase) return;
  const Matrix63d UD = U * data.D3_inv[i];
  Matrix6d Ia = IA;
  Ia.noalias() -= UD * U.transpose();
  Vector6d pa = data.pA[i];
  pa.noalias() += Ia * data.c[i];
  pa.noalias() += UD * data.u3[i];
  AddInertiaToParent(data.X_parent[i], Ia, &data.IA[body.parent]);
  data.pA[body.parent] += ForceToParent(data.X_parent[i], pa);
}

// Pass 3 for body i on a ball joint: a = X a_parent + c, qdd = D^-1 (u - U^T a) (3 values into
// qdd), a += S qdd.
inline void AccelerationStep(const Vector6d& a_parent, int i, double* qdd, Data& data) {
  Vector6d& a = data.a[i];
  a = MotionToChild(data.X_parent[i], a_parent) + data.c[i];
  const Vector3d w_dot = data.D3_inv[i] * (data.u3[i] - data.U3[i].transpose() * a);
  for (int k = 0; k < 3; ++k) qdd[k] = w_dot(k);
  a.head<3>() += w_dot;
}

}  // namespace mbstream::ball_aba

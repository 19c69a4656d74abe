// Aba for a model with free bodies or ball joints: a free root's own steps (free_joint.h), a
// ball joint's (ball_aba_steps.h) and, for every other body, the specialised passes of
// fixed-base trees (aba_passes.h: the axis kernels and the joint shapes) at the body's
// coordinates q(q_index), qd(v_index), tau(v_index). The free root's articulated inertia is
// then solved for its acceleration: a_B = IA^-1 (S^-T tau - pA).
#include <Eigen/Cholesky>

#include "server/dynamics/aba_passes.h"
#include "server/dynamics/ball_aba_steps.h"
#include "server/dynamics/free_tree.h"
#include "server/kinematics/ball_joint.h"
#include "server/kinematics/free_joint.h"
#include "shared/common/check.h"

namespace mbstream::free_tree {

namespace {

// Pass 1 for a free root: pose, velocity, velocity product, its own inertia and bias force.
void FreeForwardPass(const Body& body, int i, ConstVector q, ConstVector qd, Data& data) {
  Pose& X = data.X_parent[i];
  free_joint::Transform(q.data() + body.q_index, &X);
  data.v[i] = free_joint::Motion(X.R, qd.data() + body.v_index);
  data.c[i] = free_joint::RateProduct(data.v[i]);
  data.IA[i] = data.I[i];
  data.pA[i] = CrossForce(data.v[i], body.inertia.Apply(data.v[i]));
}

// Pass 1 for a ball joint: pose, velocity, velocity product, its own inertia and bias force.
void BallForwardPass(const Body& body, int i, ConstVector q, ConstVector qd, Data& data) {
  Pose& X = data.X_parent[i];
  ball_joint::Transform(body.joint, q.data() + body.q_index, &X);
  const Vector6d vJ = ball_joint::Motion(qd.data() + body.v_index);
  if (body.parent == kBase) {
    data.v[i] = vJ;
    data.c[i].setZero();
  } else {
    data.v[i] = MotionToChild(X, data.v[body.parent]) + vJ;
    data.c[i] = CrossMotion(data.v[i], vJ);
  }
  data.IA[i] = data.I[i];
  data.pA[i] = CrossForce(data.v[i], body.inertia.Apply(data.v[i]));
}

// Pass 3 for a free root: its acceleration from its whole subtree's articulated inertia.
void FreeAccelerationPass(const Body& body, int i, const Vector6d& a_base, ConstVector tau,
                          Data& data) {
  const Pose& X = data.X_parent[i];
  Vector6d& a = data.a[i];
  a = MotionToChild(X, a_base) + data.c[i];
  aba_passes::FillLowerTriangle(data.IA[i]);  // the children added their upper triangles
  const Eigen::LLT<Matrix6d> llt(data.IA[i]);
  MBSTREAM_CHECK_MSG(llt.info() == Eigen::Success,
                     "articulated inertia of a free body is not positive definite");
  const Vector6d a_B =
      llt.solve(free_joint::CoordinatesToForce(X.R, tau.data() + body.v_index) - data.pA[i]);
  free_joint::MotionToCoordinates(X.R, a_B - a, data.qdd.data() + body.v_index);
  a = a_B;
}

}  // namespace

const Eigen::VectorXd& Aba(const Model& model, Data& data, ConstVector q, ConstVector qd,
                           ConstVector tau) {
  using aba_passes::DispatchStep;
  const int n = model.num_bodies();
  for (int i = 0; i < n; ++i) {
    const Body& body = model.bodies[i];
    if (body.free()) {
      FreeForwardPass(body, i, q, qd, data);
      continue;
    }
    if (body.ball()) {
      BallForwardPass(body, i, q, qd, data);
      continue;
    }
    const double qi = q(body.q_index), qdi = qd(body.v_index);
    DispatchStep(
        body.joint,
        [&](auto K, auto L) { aba_passes::ForwardPassAboutAxis<K(), L()>(body, i, qi, qdi, data); },
        [&](auto shape) { aba_passes::ForwardPass<shape()>(body, i, qi, qdi, data); });
  }
  for (int i = n - 1; i >= 0; --i) {
    const Body& body = model.bodies[i];
    if (body.free()) continue;  // a root: solved in pass 3
    if (body.ball()) {
      ball_aba::BackwardStep(body, i, tau.data() + body.v_index, data);
      continue;
    }
    const double taui = tau(body.v_index);
    DispatchStep(
        body.joint,
        [&](auto K, auto L) { aba_passes::BackwardPassAboutAxis<K(), L()>(body, i, taui, data); },
        [&](auto shape) { aba_passes::BackwardPass<shape()>(body, i, taui, data); });
  }
  Vector6d a_base = Vector6d::Zero();
  a_base.tail<3>() = -model.gravity;  // gravity as an upward acceleration of the base
  for (int i = 0; i < n; ++i) {
    const Body& body = model.bodies[i];
    if (body.free()) {
      FreeAccelerationPass(body, i, a_base, tau, data);
      continue;
    }
    const Vector6d& a_parent = body.parent == kBase ? a_base : data.a[body.parent];
    const int v = body.v_index;
    if (body.ball()) {
      ball_aba::AccelerationStep(a_parent, i, data.qdd.data() + v, data);
      continue;
    }
    DispatchStep(
        body.joint,
        [&](auto K, auto L) {
          aba_passes::AccelerationPassAboutAxis<K(), L()>(a_parent, i, v, data);
        },
        [&](auto shape) { aba_passes::AccelerationPass<shape()>(a_parent, i, v, data); });
  }
  return data.qdd;
}

}  // namespace mbstream::free_tree

// The articulated-body algorithm's three per-body passes (Featherstone, RBDA 7.3),
// specialised on a joint's Shape: shared by Aba (aba.cc) and HybridAba
// (hybrid_dynamics.cc). Internal to server/dynamics.
#pragma once

#include "common/check.h"
#include "server/kinematics/joint_inertia_transform.h"
#include "server/kinematics/joint_spatial_transform.h"
#include "server/kinematics/joint_transform.h"
#include "server/model/data.h"
#include "server/model/model.h"

namespace mbstream::aba_passes {

// The three passes' work for body i, specialised on its joint's Shape (see
// joint_spatial_transform.h). S_index >= 0 (S a coordinate unit vector) reads IA S as a
// column; otherwise the products are formed.

// Pass 1 (base to tips): pose in the parent, velocity, velocity-product acceleration c,
// articulated inertia and bias force initialised to the body's own.
template <int Shape>
void ForwardPass(const Body& body, int i, double q, double qd, Data& data) {
  JointTransformOfShape<Shape>(body.joint, q, &data.X_parent[i]);
  const Vector6d vJ = data.S[i] * qd;
  if (body.parent == kBase) {
    data.v[i] = vJ;
    data.c[i].setZero();
  } else {
    data.v[i] = MotionToChildAcross<Shape>(data.X_parent[i], data.v[body.parent]) + vJ;
    data.c[i] = CrossMotion(data.v[i], vJ);
  }
  data.IA[i] = data.I[i];
  data.pA[i] = CrossForce(data.v[i], body.inertia.Apply(data.v[i]));
}

// Pass 2 (tips to base): U, D, u of body i, and its projected articulated inertia and
// bias force added to its parent's.
template <int Shape>
void BackwardPass(const Body& body, int i, double tau, Data& data) {
  const int k = data.S_index[i];
  Matrix6d& IA = data.IA[i];
  if (k >= 0) {
    data.U[i] = IA.col(k);
    data.D[i] = data.U[i](k) + body.joint.armature;
    data.u[i] = tau - data.pA[i](k);
  } else {
    data.U[i].noalias() = IA * data.S[i];
    data.D[i] = data.S[i].dot(data.U[i]) + body.joint.armature;
    data.u[i] = tau - data.S[i].dot(data.pA[i]);
  }
  MBSTREAM_CHECK_MSG(data.D[i] > 0.0, "articulated inertia of a joint is not positive");
  if (body.parent == kBase) return;
  const double inv_D = 1.0 / data.D[i];
  const Vector6d& U = data.U[i];
  // pa = pA + Ia c + U u / D with Ia = IA - U U^T / D, i.e. pA + IA c + U (u - U.c) / D
  // (IA still whole here).
  Vector6d pa = data.pA[i] + U * ((data.u[i] - U.dot(data.c[i])) * inv_D);
  pa.noalias() += IA * data.c[i];
  AddProjectedInertiaAcross<Shape>(data.X_parent[i], IA, U, inv_D, &data.IA[body.parent]);
  data.pA[body.parent] += ForceToParentAcross<Shape>(data.X_parent[i], pa);
}

// Pass 3 (base to tips): the joint's acceleration and the body's.
template <int Shape>
void AccelerationPass(const Vector6d& a_parent, int i, Data& data) {
  Vector6d& a = data.a[i];
  a = MotionToChildAcross<Shape>(data.X_parent[i], a_parent) + data.c[i];
  data.qdd(i) = (data.u[i] - data.U[i].dot(a)) / data.D[i];
  const int k = data.S_index[i];
  if (k >= 0) {
    a(k) += data.qdd(i);
  } else {
    a += data.S[i] * data.qdd(i);
  }
}

// Pass 1 over every body.
inline void ForwardPasses(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                          const Eigen::Ref<const Eigen::VectorXd>& qd, Data& data) {
  for (int i = 0; i < model.num_dofs(); ++i) {
    const Body& body = model.bodies[i];
    DispatchJointShape(body.joint,
                       [&](auto shape) { ForwardPass<shape()>(body, i, q(i), qd(i), data); });
  }
}

}  // namespace mbstream::aba_passes

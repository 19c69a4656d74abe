#include "server/dynamics/aba.h"

#include "common/check.h"
#include "server/kinematics/joint_inertia_transform.h"
#include "server/kinematics/joint_spatial_transform.h"
#include "server/kinematics/joint_transform.h"

namespace mbstream {

namespace {

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

// Hybrid dynamics, pass 2 for a prescribed joint (qdd given): its subtree moves with a
// known relative acceleration, so the whole articulated inertia reaches the parent and the
// bias gains IA (c + S qdd) (Featherstone, RBDA 9.2).
template <int Shape>
void PrescribedBackwardPass(const Body& body, int i, double qdd, Data& data) {
  if (body.parent == kBase) return;
  Vector6d accel = data.c[i];
  const int k = data.S_index[i];
  if (k >= 0) {
    accel(k) += qdd;
  } else {
    accel += data.S[i] * qdd;
  }
  Vector6d pa = data.pA[i];
  pa.noalias() += data.IA[i] * accel;
  AddInertiaAcross<Shape>(data.X_parent[i], data.IA[i], &data.IA[body.parent]);
  data.pA[body.parent] += ForceToParentAcross<Shape>(data.X_parent[i], pa);
}

// Hybrid dynamics, pass 3 for a prescribed joint: the body's acceleration and the joint
// force that produces it, S^T (IA a + pA) + armature qdd (IA, pA whole: never projected).
template <int Shape>
void PrescribedAccelerationPass(const Body& body, const Vector6d& a_parent, int i, Data& data) {
  Vector6d& a = data.a[i];
  const double qdd = data.qdd(i);
  a = MotionToChildAcross<Shape>(data.X_parent[i], a_parent) + data.c[i];
  const int k = data.S_index[i];
  if (k >= 0) {
    a(k) += qdd;
    data.tau(i) = data.IA[i].row(k).dot(a) + data.pA[i](k);
  } else {
    a += data.S[i] * qdd;
    data.tau(i) = data.S[i].dot(data.IA[i] * a + data.pA[i]);
  }
  data.tau(i) += body.joint.armature * qdd;
}

// ABA (kHybrid false: `prescribed` unused) or hybrid dynamics (joints with prescribed[i]
// take data.qdd(i) as given and get their force in data.tau(i)).
template <bool kHybrid>
void ArticulatedBodyPasses(const Model& model, Data& data,
                           const Eigen::Ref<const Eigen::VectorXd>& q,
                           const Eigen::Ref<const Eigen::VectorXd>& qd,
                           const Eigen::Ref<const Eigen::VectorXd>& tau,
                           const std::vector<unsigned char>* prescribed) {
  const int n = model.num_dofs();
  for (int i = 0; i < n; ++i) {
    const Body& body = model.bodies[i];
    DispatchJointShape(body.joint,
                       [&](auto shape) { ForwardPass<shape()>(body, i, q(i), qd(i), data); });
  }
  for (int i = n - 1; i >= 0; --i) {
    const Body& body = model.bodies[i];
    if (kHybrid && (*prescribed)[i]) {
      DispatchJointShape(body.joint, [&](auto shape) {
        PrescribedBackwardPass<shape()>(body, i, data.qdd(i), data);
      });
    } else {
      DispatchJointShape(body.joint,
                         [&](auto shape) { BackwardPass<shape()>(body, i, tau(i), data); });
    }
  }
  Vector6d a_base = Vector6d::Zero();
  a_base.tail<3>() = -model.gravity;  // gravity as an upward acceleration of the base
  for (int i = 0; i < n; ++i) {
    const Body& body = model.bodies[i];
    const Vector6d& a_parent = body.parent == kBase ? a_base : data.a[body.parent];
    if (kHybrid && (*prescribed)[i]) {
      DispatchJointShape(body.joint, [&](auto shape) {
        PrescribedAccelerationPass<shape()>(body, a_parent, i, data);
      });
    } else {
      DispatchJointShape(body.joint,
                         [&](auto shape) { AccelerationPass<shape()>(a_parent, i, data); });
    }
  }
}

}  // namespace

const Eigen::VectorXd& Aba(const Model& model, Data& data,
                           const Eigen::Ref<const Eigen::VectorXd>& q,
                           const Eigen::Ref<const Eigen::VectorXd>& qd,
                           const Eigen::Ref<const Eigen::VectorXd>& tau) {
  const int n = model.num_dofs();
  MBSTREAM_CHECK(q.size() == n && qd.size() == n && tau.size() == n);
  ArticulatedBodyPasses<false>(model, data, q, qd, tau, nullptr);
  return data.qdd;
}

const Eigen::VectorXd& HybridAba(const Model& model, Data& data,
                                 const Eigen::Ref<const Eigen::VectorXd>& q,
                                 const Eigen::Ref<const Eigen::VectorXd>& qd,
                                 const Eigen::Ref<const Eigen::VectorXd>& tau,
                                 const Eigen::Ref<const Eigen::VectorXd>& qdd,
                                 const std::vector<unsigned char>& prescribed) {
  const int n = model.num_dofs();
  MBSTREAM_CHECK(q.size() == n && qd.size() == n && tau.size() == n && qdd.size() == n &&
                 static_cast<int>(prescribed.size()) == n);
  for (int i = 0; i < n; ++i) {
    if (prescribed[i]) data.qdd(i) = qdd(i);
  }
  ArticulatedBodyPasses<true>(model, data, q, qd, tau, &prescribed);
  return data.qdd;
}

}  // namespace mbstream

#include "server/dynamics/hybrid_dynamics.h"

#include "server/dynamics/aba_passes.h"
#include "server/dynamics/free_tree.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

using aba_passes::AccelerationPass;
using aba_passes::BackwardPass;

// Hybrid dynamics, pass 2 for a prescribed joint (qdd given): its subtree moves with a
// known relative acceleration, so the whole articulated inertia reaches the parent and the
// bias gains IA (c + S qdd) (Featherstone, RBDA 9.2).
template <int Shape>
void PrescribedBackwardPass(const Body& body, int i, double qdd, Data& data) {
  aba_passes::FillLowerTriangle(data.IA[i]);  // its children added their upper triangles
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

}  // namespace

const Eigen::VectorXd& HybridAba(const Model& model, Data& data,
                                 const Eigen::Ref<const Eigen::VectorXd>& q,
                                 const Eigen::Ref<const Eigen::VectorXd>& qd,
                                 const Eigen::Ref<const Eigen::VectorXd>& tau,
                                 const Eigen::Ref<const Eigen::VectorXd>& qdd,
                                 const std::vector<unsigned char>& prescribed) {
  if (model.has_quaternions()) {
    const int nv = model.nv();
    MBSTREAM_CHECK(q.size() == model.nq() && qd.size() == nv && tau.size() == nv &&
                   qdd.size() == nv && static_cast<int>(prescribed.size()) == nv);
    return free_tree::HybridAba(model, data, q, qd, tau, qdd, &prescribed);
  }
  const int n = model.num_bodies();
  MBSTREAM_CHECK(q.size() == n && qd.size() == n && tau.size() == n && qdd.size() == n &&
                 static_cast<int>(prescribed.size()) == n);
  for (int i = 0; i < n; ++i) {
    if (prescribed[i]) data.qdd(i) = qdd(i);
  }
  // Aba's three passes, with the prescribed joints' own pass 2 and pass 3.
  aba_passes::ForwardPasses(model, q, qd, data);
  for (int i = n - 1; i >= 0; --i) {
    const Body& body = model.bodies[i];
    aba_passes::DispatchStep(
        body.joint,
        [&](auto K, auto L) {
          if (prescribed[i]) {
            PrescribedBackwardPass<K()>(body, i, data.qdd(i), data);
          } else {
            aba_passes::BackwardPassAboutAxis<K(), L()>(body, i, tau(i), data);
          }
        },
        [&](auto shape) {
          if (prescribed[i]) {
            PrescribedBackwardPass<shape()>(body, i, data.qdd(i), data);
          } else {
            BackwardPass<shape()>(body, i, tau(i), data);
          }
        });
  }
  Vector6d a_base = Vector6d::Zero();
  a_base.tail<3>() = -model.gravity;
  for (int i = 0; i < n; ++i) {
    const Body& body = model.bodies[i];
    const Vector6d& a_parent = body.parent == kBase ? a_base : data.a[body.parent];
    aba_passes::DispatchStep(
        body.joint,
        [&](auto K, auto L) {
          if (prescribed[i]) {
            PrescribedAccelerationPass<K()>(body, a_parent, i, data);
          } else {
            aba_passes::AccelerationPassAboutAxis<K(), L()>(a_parent, i, data);
          }
        },
        [&](auto shape) {
          if (prescribed[i]) {
            PrescribedAccelerationPass<shape()>(body, a_parent, i, data);
          } else {
            AccelerationPass<shape()>(a_parent, i, data);
          }
        });
  }
  return data.qdd;
}

}  // namespace mbstream

// The articulated-body algorithm's three per-body passes (Featherstone, RBDA 7.3),
// specialised on a joint's Shape: shared by Aba (aba.cc) and HybridAba
// (hybrid_dynamics.cc). Internal to server/dynamics.
#pragma once

#include <cstring>
#include <type_traits>
#include <utility>

#include "server/dynamics/axis_inertia_move.h"
#include "server/dynamics/axis_joint_steps.h"
#include "server/kinematics/joint_inertia_transform.h"
#include "server/kinematics/joint_spatial_transform.h"
#include "server/kinematics/joint_transform.h"
#include "server/model/data.h"
#include "server/model/model.h"
#include "shared/common/check.h"

namespace mbstream::aba_passes {

// The articulated inertias IA are kept as their upper triangles only (entries (r, q) with
// r <= q; axis_inertia_move.h): the passes for an axis joint read and add only those, and
// the general passes first copy the upper triangle into the lower one.
inline void FillLowerTriangle(Matrix6d& M) {
  for (int q = 0; q < 6; ++q) {
    for (int r = q + 1; r < 6; ++r) M(r, q) = M(q, r);
  }
}

// The upper triangle of `from` into `to`'s, column by column (column q's rows 0..q are
// contiguous: 21 doubles in 6 copies instead of 36).
[[gnu::always_inline]] inline void CopyUpperTriangle(const Matrix6d& from, Matrix6d& to) {
  axis_joint::Unroll<6>([&](auto q) {
    std::memcpy(to.data() + 6 * q, from.data() + 6 * q, (q + 1) * sizeof(double));
  });
}

// Entry (r, q) of a symmetric matrix of which only the upper triangle is kept.
template <int r, int q>
[[gnu::always_inline]] inline double Upper(const Matrix6d& M) {
  if constexpr (r <= q) {
    return M.data()[r + 6 * q];  // column-major
  } else {
    return M.data()[q + 6 * r];
  }
}

// The three passes for a revolute joint about coordinate axis K with an unrotated origin whose
// offset has shape L (axis_joint::OffsetMayBeNonzero), in scalars (axis_joint_steps.h):
// S = e_K, and c = v x (S qd) is zero in components K and 3 + K.

template <int K, int L>
void ForwardPassAboutAxis(const Body& body, int i, double q, double qd, Data& data) {
  using namespace axis_joint;
  const Vector3d& p = body.joint.X_PJ.p;
  const AxisRotation r = WritePose<K>(q, p, &data.X_parent[i]);
  double* v = data.v[i].data();
  double* c = data.c[i].data();
  if (body.parent == kBase) {
    for (int e = 0; e < 6; ++e) v[e] = c[e] = 0.0;
  } else {
    MotionToChild<K, L>(r, p.data(), data.v[body.parent].data(), v);
    // c = v x (e_K qd), AddCrossJointRate written as assignments.
    constexpr int i1 = (K + 1) % 3, i2 = (K + 2) % 3;
    c[K] = c[3 + K] = 0.0;
    c[i1] = v[i2] * qd;
    c[i2] = -(v[i1] * qd);
    c[3 + i1] = v[3 + i2] * qd;
    c[3 + i2] = -(v[3 + i1] * qd);
  }
  v[K] += qd;
  CopyUpperTriangle(data.I[i], data.IA[i]);
  double h[6];
  ApplyInertia(body.inertia, v, h);
  CrossForce<false>(v, h, data.pA[i].data());
}

template <int K, int L>
void BackwardPassAboutAxis(const Body& body, int i, double tau, Data& data) {
  using namespace axis_joint;
  const Matrix6d& IA = data.IA[i];  // upper triangle
  const double* pA = data.pA[i].data();
  double* U = data.U[i].data();
  Unroll<6>([&](auto e) { U[e] = Upper<e, K>(IA); });
  const double D = U[K] + body.joint.armature;
  const double u = tau - pA[K];
  data.D[i] = D;
  data.u[i] = u;
  MBSTREAM_CHECK_MSG(D > 0.0, "articulated inertia of a joint is not positive");
  const double inv_D = 1.0 / D;
  data.inv_D[i] = inv_D;  // pass 3 multiplies: no division on its parent-to-child chain
  if (body.parent == kBase) return;
  const double* c = data.c[i].data();
  double pa[6];
  const Pose& X = data.X_parent[i];
  const AxisRotation r = RotationOf<K>(X);
  if (body.joint.armature == 0.0) {
    AddProjectedInertiaToParent<K, L, true>(r, X.p.data(), IA, U, inv_D, pA, c, u, pa,
                                            &data.IA[body.parent]);
  } else {
    AddProjectedInertiaToParent<K, L, false>(r, X.p.data(), IA, U, inv_D, pA, c, u, pa,
                                             &data.IA[body.parent]);
  }
  AddForceToParent<K, L>(r, X.p.data(), pa, data.pA[body.parent].data());
}

// The joint's acceleration goes to data.qdd(v): v = i in a fixed-base tree, Body::v_index with
// free bodies (free_aba.cc).
template <int K, int L>
void AccelerationPassAboutAxis(const Vector6d& a_parent, int i, int v, Data& data) {
  using namespace axis_joint;
  const Pose& X = data.X_parent[i];
  double* a = data.a[i].data();
  const double* c = data.c[i].data();
  const double* U = data.U[i].data();
  double x[6];
  MotionToChild<K, L>(RotationOf<K>(X), X.p.data(), a_parent.data(), x);
  // a = X^T a_parent + c (c_K = c_(3 + K) = 0), qdd = (u - U.a) / D, a += e_K qdd: the
  // chain from the parent's acceleration to the child's (every body waits for its parent's)
  // kept short, U.a summed pairwise and no division.
  Unroll<6>([&](auto e) {
    if constexpr (e != K && e != 3 + K) x[e] += c[e];
  });
  const double Ua =
      ((U[0] * x[0] + U[1] * x[1]) + (U[2] * x[2] + U[3] * x[3])) + (U[4] * x[4] + U[5] * x[5]);
  const double qdd = (data.u[i] - Ua) * data.inv_D[i];
  data.qdd(v) = qdd;
  x[K] += qdd;
  for (int e = 0; e < 6; ++e) a[e] = x[e];
}

template <int K, int L>
void AccelerationPassAboutAxis(const Vector6d& a_parent, int i, Data& data) {
  AccelerationPassAboutAxis<K, L>(a_parent, i, i, data);
}

// The three passes' work for body i, specialised on its joint's Shape (see
// joint_spatial_transform.h). S_index >= 0 (S a coordinate unit vector) reads IA S as a
// column; otherwise the products are formed.

// Pass 1 (base to tips): pose in the parent, velocity, velocity-product acceleration c,
// articulated inertia and bias force initialised to the body's own.
template <int Shape>
void ForwardPass(const Body& body, int i, double q, double qd, Data& data) {
  if constexpr (Shape >= 0) {
    ForwardPassAboutAxis<Shape, kAnyOffset>(
        body, i, q, qd, data);  // any offset: also right without Joint::axis_kernel
    return;
  }
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
  if constexpr (Shape >= 0) {
    BackwardPassAboutAxis<Shape, kAnyOffset>(
        body, i, tau, data);  // any offset: also right without Joint::axis_kernel
    return;
  }
  const int k = data.S_index[i];
  Matrix6d& IA = data.IA[i];
  FillLowerTriangle(IA);
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
void AccelerationPass(const Vector6d& a_parent, int i, int v, Data& data) {
  if constexpr (Shape >= 0) {
    AccelerationPassAboutAxis<Shape, kAnyOffset>(
        a_parent, i, v, data);  // any offset: also right without Joint::axis_kernel
    return;
  }
  Vector6d& a = data.a[i];
  a = MotionToChildAcross<Shape>(data.X_parent[i], a_parent) + data.c[i];
  data.qdd(v) = (data.u[i] - data.U[i].dot(a)) / data.D[i];
  const int k = data.S_index[i];
  if (k >= 0) {
    a(k) += data.qdd(v);
  } else {
    a += data.S[i] * data.qdd(v);
  }
}

template <int Shape>
void AccelerationPass(const Vector6d& a_parent, int i, Data& data) {
  AccelerationPass<Shape>(a_parent, i, i, data);
}

// Joint::axis_kernel C = 5 K + (L, or 4 for kAnyOffset) as the constants K and L.
template <int C>
using KernelAxis = std::integral_constant<int, C / 5>;
template <int C>
using KernelOffset = std::integral_constant<int, (C % 5 == 4 ? kAnyOffset : C % 5)>;

// Calls axis(KernelAxis<C>{}, KernelOffset<C>{}) for a joint with axis kernel C
// (Joint::axis_kernel: a revolute joint about coordinate axis K with an unrotated origin of
// offset shape L), else other(std::integral_constant<int, Shape>{}) for its JointShape: one
// jump per body and pass (GCC makes the comparisons one jump table).
template <typename FAxis, typename FOther>
[[gnu::always_inline]] inline void DispatchStep(const Joint& joint, FAxis&& axis, FOther&& other) {
  const int kernel = joint.axis_kernel;
  const auto try_kernels = [&]<int... C>(std::integer_sequence<int, C...>) {
    return ((kernel == C && (axis(KernelAxis<C>{}, KernelOffset<C>{}), true)) || ...);
  };
  if (!try_kernels(std::make_integer_sequence<int, 15>{})) DispatchJointShape(joint, other);
}

// Pass 1 over every body.
inline void ForwardPasses(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& q,
                          const Eigen::Ref<const Eigen::VectorXd>& qd, Data& data) {
  for (int i = 0; i < model.num_bodies(); ++i) {
    const Body& body = model.bodies[i];
    DispatchStep(
        body.joint,
        [&](auto K, auto L) { ForwardPassAboutAxis<K(), L()>(body, i, q(i), qd(i), data); },
        [&](auto shape) { ForwardPass<shape()>(body, i, q(i), qd(i), data); });
  }
}

}  // namespace mbstream::aba_passes

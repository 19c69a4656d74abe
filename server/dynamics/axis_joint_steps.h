// The recursive algorithms' per-body steps for the commonest joint, written out in scalars:
// a revolute joint about coordinate axis K (0, 1, 2 = x, y, z) with an unrotated origin
// (JointShape(joint) == K, server/kinematics/joint_spatial_transform.h; every joint of the
// IRB 1600 and of most industrial arms). Its motion subspace S is the unit vector e_K, so
// S qd adds to one component, v x (S qd) is four products, S^T f picks a component, and the
// joint's pose is a plane rotation by (cos q, sin q) and a constant offset p.
//
// Spatial vectors are 6 doubles, [angular; linear] as in server/math/spatial.h. The values
// are those of the general path's Eigen expressions, operation for operation, but for the
// sign of zeros and for the joint's (cos, sin), which come from SinCos (server/math/sin_cos.h:
// within one ulp of the C library's); tests/server/kernels_test.cc holds them to 1e-12 of the
// general path. Written in scalars because Eigen's two-wide SSE2 packets on 3-vectors cost
// more shuffles than they save here. Internal to server/dynamics; allocate nothing.
#pragma once

#include <type_traits>

#include "server/math/rigid_inertia.h"
#include "server/math/sin_cos.h"
#include "server/math/spatial.h"
#include "server/model/joint.h"

namespace mbstream::axis_joint {

// The joint's pose in its parent X_PB = (R(q) about K, p), and its (cos q, sin q).
struct AxisRotation {
  double c;
  double s;
};

template <int K>
[[gnu::always_inline]] inline AxisRotation WritePose(double q, const Vector3d& p, Pose* X_PB) {
  AxisRotation r;
  SinCos(q, &r.s, &r.c);
  constexpr int i = (K + 1) % 3, j = (K + 2) % 3;
  double* R = X_PB->R.data();  // column-major
  for (int e = 0; e < 9; ++e) R[e] = 0.0;
  R[K + 3 * K] = 1.0;
  R[i + 3 * i] = r.c;
  R[i + 3 * j] = -r.s;
  R[j + 3 * i] = r.s;
  R[j + 3 * j] = r.c;
  X_PB->p = p;
  return r;
}

// The (cos, sin) that WritePose wrote into R.
template <int K>
[[gnu::always_inline]] inline AxisRotation RotationOf(const Pose& X_PB) {
  constexpr int i = (K + 1) % 3, j = (K + 2) % 3;
  return AxisRotation{X_PB.R(i, i), X_PB.R(j, i)};
}

// Offset shape L of a joint's origin p (Joint::offset_axis): 0, 1, 2 = p on that coordinate
// axis, kNoOffset = p = 0, kAnyOffset = any p. The steps below take L as a template argument
// and drop the products by p's components that are zero for that shape.
constexpr bool OffsetMayBeNonzero(int L, int m) { return L == kAnyOffset || L == m; }

// base + (w x p)_r (kPFirst: base + (p x w)_r), without the products by p's zero components.
template <int L, int r, bool kPFirst = false>
[[gnu::always_inline]] inline double AddCrossOffset(double base, const double* w, const double* p) {
  constexpr int r1 = (r + 1) % 3, r2 = (r + 2) % 3;
  // (w x p)_r = w[r1] p[r2] - w[r2] p[r1]; (p x w)_r = p[r1] w[r2] - p[r2] w[r1].
  constexpr int plus = kPFirst ? r1 : r2, minus = kPFirst ? r2 : r1;
  constexpr bool has_plus = OffsetMayBeNonzero(L, plus), has_minus = OffsetMayBeNonzero(L, minus);
  if constexpr (has_plus && has_minus) {
    if constexpr (kPFirst) {
      return base + (p[r1] * w[r2] - p[r2] * w[r1]);
    } else {
      return base + (w[r1] * p[r2] - w[r2] * p[r1]);
    }
  } else if constexpr (has_plus) {
    return base + (kPFirst ? p[r1] * w[r2] : w[r1] * p[r2]);
  } else if constexpr (has_minus) {
    return base - (kPFirst ? p[r2] * w[r1] : w[r2] * p[r1]);
  } else {
    return base;
  }
}

// out = X^T m: the parent's motion vector m (at the parent's origin, in its axes) in the
// child's frame, [R^T w; R^T (v + w x p)], for p of offset shape L.
template <int K, int L = kAnyOffset>
[[gnu::always_inline]] inline void MotionToChild(AxisRotation r, const double* p, const double* m,
                                                 double* out) {
  constexpr int i = (K + 1) % 3, j = (K + 2) % 3;
  const double t[3] = {AddCrossOffset<L, 0>(m[3], m, p), AddCrossOffset<L, 1>(m[4], m, p),
                       AddCrossOffset<L, 2>(m[5], m, p)};
  out[K] = m[K];
  out[i] = r.c * m[i] + r.s * m[j];
  out[j] = r.c * m[j] - r.s * m[i];
  out[3 + K] = t[K];
  out[3 + i] = r.c * t[i] + r.s * t[j];
  out[3 + j] = r.c * t[j] - r.s * t[i];
}

// out += X^* f: the child's force vector f (moment about the child's origin, in its axes)
// added to the parent's, [R n + p x (R f); R f], for p of offset shape L.
template <int K, int L = kAnyOffset>
[[gnu::always_inline]] inline void AddForceToParent(AxisRotation r, const double* p,
                                                    const double* f, double* out) {
  constexpr int i = (K + 1) % 3, j = (K + 2) % 3;
  double n[3], g[3];
  n[K] = f[K];
  n[i] = r.c * f[i] - r.s * f[j];
  n[j] = r.s * f[i] + r.c * f[j];
  g[K] = f[3 + K];
  g[i] = r.c * f[3 + i] - r.s * f[3 + j];
  g[j] = r.s * f[3 + i] + r.c * f[3 + j];
  out[0] += AddCrossOffset<L, 0, true>(n[0], g, p);
  out[1] += AddCrossOffset<L, 1, true>(n[1], g, p);
  out[2] += AddCrossOffset<L, 2, true>(n[2], g, p);
  out[3] += g[0];
  out[4] += g[1];
  out[5] += g[2];
}

// a += v x (e_K qd), the velocity-product term (Featherstone's crm(v) S qd).
template <int K>
[[gnu::always_inline]] inline void AddCrossJointRate(const double* v, double qd, double* a) {
  constexpr int i = (K + 1) % 3, j = (K + 2) % 3;
  a[i] += v[j] * qd;
  a[j] -= v[i] * qd;
  a[3 + i] += v[3 + j] * qd;
  a[3 + j] -= v[3 + i] * qd;
}

// h = I m for the body's rigid inertia (RigidInertia::Apply).
[[gnu::always_inline]] inline void ApplyInertia(const RigidInertia& body, const double* m,
                                                double* h) {
  const double* c = body.com.data();
  const double* I = body.inertia_com.data();  // column-major, symmetric
  const double mass = body.mass;
  const double p[3] = {mass * (m[3] + (m[1] * c[2] - m[2] * c[1])),
                       mass * (m[4] + (m[2] * c[0] - m[0] * c[2])),
                       mass * (m[5] + (m[0] * c[1] - m[1] * c[0]))};
  h[0] = (I[0] * m[0] + I[3] * m[1]) + I[6] * m[2];
  h[1] = (I[1] * m[0] + I[4] * m[1]) + I[7] * m[2];
  h[2] = (I[2] * m[0] + I[5] * m[1]) + I[8] * m[2];
  h[0] += c[1] * p[2] - c[2] * p[1];
  h[1] += c[2] * p[0] - c[0] * p[2];
  h[2] += c[0] * p[1] - c[1] * p[0];
  h[3] = p[0];
  h[4] = p[1];
  h[5] = p[2];
}

// out = v x* h (Featherstone's crf), or out += it with kAdd.
template <bool kAdd>
[[gnu::always_inline]] inline void CrossForce(const double* v, const double* h, double* out) {
  const double r[6] = {(v[1] * h[2] - v[2] * h[1]) + (v[4] * h[5] - v[5] * h[4]),
                       (v[2] * h[0] - v[0] * h[2]) + (v[5] * h[3] - v[3] * h[5]),
                       (v[0] * h[1] - v[1] * h[0]) + (v[3] * h[4] - v[4] * h[3]),
                       v[1] * h[5] - v[2] * h[4],
                       v[2] * h[3] - v[0] * h[5],
                       v[0] * h[4] - v[1] * h[3]};
  for (int e = 0; e < 6; ++e) {
    if constexpr (kAdd) {
      out[e] += r[e];
    } else {
      out[e] = r[e];
    }
  }
}

}  // namespace mbstream::axis_joint

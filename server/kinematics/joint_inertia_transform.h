// Moving a 6x6 spatial inertia across a joint, from the child body's frame to its parent's:
// I_P += X^T I_B X. The articulated-body and composite-rigid-body algorithms spend most of
// their time here, so joints about a coordinate axis with an unrotated origin (most robot
// arms, the IRB 1600 included) take a fast path: plane rotations and cross products
// instead of 3x3 matrix products. Its small loops carry `#pragma GCC unroll` (GCC 12 otherwise
// keeps the triangular ones rolled, with the blocks spilled to the stack).
#pragma once

#include "server/kinematics/joint_spatial_transform.h"
#include "server/math/spatial.h"
#include "server/model/joint.h"

namespace mbstream {

namespace internal {

// M <- R M R^T for R the rotation by (cos c, sin s) about coordinate axis K.
template <int K>
inline void RotateAboutCoordinateAxis(double c, double s, Matrix3d& M) {
  constexpr int i = (K + 1) % 3, j = (K + 2) % 3;
#pragma GCC unroll 8
  for (int col = 0; col < 3; ++col) {
    const double mi = M(i, col), mj = M(j, col);
    M(i, col) = c * mi - s * mj;
    M(j, col) = s * mi + c * mj;
  }
#pragma GCC unroll 8
  for (int row = 0; row < 3; ++row) {
    const double mi = M(row, i), mj = M(row, j);
    M(row, i) = c * mi - s * mj;
    M(row, j) = s * mi + c * mj;
  }
}

// The fast path of AddInertiaAcrossJoint for X_AB = (R, p) with R a rotation by (c, s) about
// coordinate axis K (K < 0: R = I). I_B = [A B; B^T C] with A and C symmetric (a spatial
// inertia or an articulated one): only their upper triangles are read and computed. With
// kProject, I_B - U U^T / D (inv_D = 1 / D) is moved instead, without forming it: the
// articulated-body algorithm's projected inertia.
template <int K, bool kProject = false, bool kShift = true>
inline void AddInertiaAcrossCoordinateJoint(double c, double s, const Vector3d& p,
                                            const Matrix6d& I_B, Matrix6d* I_A,
                                            const Vector6d* U = nullptr, double inv_D = 0.0) {
  // Symmetric blocks in the parent's orientation: S' = R S R^T (6 entries each).
  double a[3][3], cc[3][3];
  Matrix3d B = I_B.topRightCorner<3, 3>();
  if constexpr (kProject) {
    double u[6], w[6];
#pragma GCC unroll 8
    for (int r = 0; r < 6; ++r) {
      u[r] = (*U)(r);
      w[r] = u[r] * inv_D;
    }
#pragma GCC unroll 8
    for (int r = 0; r < 3; ++r) {
#pragma GCC unroll 8
      for (int q = r; q < 3; ++q) {
        a[r][q] = a[q][r] = I_B(r, q) - w[r] * u[q];
        cc[r][q] = cc[q][r] = I_B(3 + r, 3 + q) - w[3 + r] * u[3 + q];
      }
#pragma GCC unroll 8
      for (int q = 0; q < 3; ++q) B(r, q) -= w[r] * u[3 + q];
    }
  } else {
#pragma GCC unroll 8
    for (int r = 0; r < 3; ++r) {
#pragma GCC unroll 8
      for (int q = r; q < 3; ++q) {
        a[r][q] = a[q][r] = I_B(r, q);
        cc[r][q] = cc[q][r] = I_B(3 + r, 3 + q);
      }
    }
  }
  if constexpr (K >= 0) {
    constexpr int k = K, i = (K + 1) % 3, j = (K + 2) % 3;
    const double cs = c * s, c2 = c * c, s2 = s * s;
#pragma GCC unroll 8
    for (auto* m : {&a, &cc}) {
      double(&x)[3][3] = *m;
      const double ki = x[k][i], kj = x[k][j], ii = x[i][i], jj = x[j][j], ij = x[i][j];
      x[k][i] = x[i][k] = c * ki - s * kj;
      x[k][j] = x[j][k] = s * ki + c * kj;
      x[i][i] = c2 * ii - 2.0 * cs * ij + s2 * jj;
      x[j][j] = s2 * ii + 2.0 * cs * ij + c2 * jj;
      x[i][j] = x[j][i] = cs * (ii - jj) + (c2 - s2) * ij;
    }
    RotateAboutCoordinateAxis<K>(c, s, B);
  }
  if constexpr (!kShift) {
    // p = 0 (the joint's origin is its parent's): the rotated blocks are the result.
    Matrix6d& out = *I_A;
#pragma GCC unroll 8
    for (int r = 0; r < 3; ++r) {
#pragma GCC unroll 8
      for (int q = 0; q < 3; ++q) {
        if (q >= r) {
          out(r, q) += a[r][q];
          out(3 + r, 3 + q) += cc[r][q];
          if (q != r) {
            out(q, r) += a[r][q];
            out(3 + q, 3 + r) += cc[r][q];
          }
        }
        out(r, 3 + q) += B(r, q);
        out(3 + q, r) += B(r, q);
      }
    }
    return;
  }
  // Shift the reference point from Bo to Ao by p (see AddInertiaToParent):
  //   TL += A + T + T^T + W, TR += B + Q, BR += C, with
  //   T = [p]x B^T, Q = [p]x C, W = [p]x C [p]x^T = Q [p]x^T.
  const double px = p.x(), py = p.y(), pz = p.z();
  // Q = [p]x C, row by row: [p]x = [0 -pz py; pz 0 -px; -py px 0].
  double Q[3][3];
#pragma GCC unroll 8
  for (int col = 0; col < 3; ++col) {
    Q[0][col] = -pz * cc[1][col] + py * cc[2][col];
    Q[1][col] = pz * cc[0][col] - px * cc[2][col];
    Q[2][col] = -py * cc[0][col] + px * cc[1][col];
  }
  // T = [p]x B^T: T(r, col) = ([p]x row r) . B(col, :).
  double T[3][3];
#pragma GCC unroll 8
  for (int col = 0; col < 3; ++col) {
    T[0][col] = -pz * B(col, 1) + py * B(col, 2);
    T[1][col] = pz * B(col, 0) - px * B(col, 2);
    T[2][col] = -py * B(col, 0) + px * B(col, 1);
  }
  // W = Q [p]x^T: W(r, q) = Q row r . ([p]x row q).
  const double P[3][3] = {{0.0, -pz, py}, {pz, 0.0, -px}, {-py, px, 0.0}};
  Matrix6d& out = *I_A;
#pragma GCC unroll 8
  for (int r = 0; r < 3; ++r) {
#pragma GCC unroll 8
    for (int q = r; q < 3; ++q) {
      const double w = Q[r][0] * P[q][0] + Q[r][1] * P[q][1] + Q[r][2] * P[q][2];
      const double tl = a[r][q] + T[r][q] + T[q][r] + w;
      out(r, q) += tl;
      if (q != r) out(q, r) += tl;
      out(3 + r, 3 + q) += cc[r][q];
      if (q != r) out(3 + q, 3 + r) += cc[r][q];
    }
  }
#pragma GCC unroll 8
  for (int r = 0; r < 3; ++r) {
#pragma GCC unroll 8
    for (int q = 0; q < 3; ++q) {
      const double tr = B(r, q) + Q[r][q];
      out(r, 3 + q) += tr;
      out(3 + q, r) += tr;
    }
  }
}

// AddInertiaAcrossCoordinateJoint<K, kProject> for a joint of Shape >= kTranslatingJoint,
// its (cos, sin) read from X_AB.R (see CoordinateRotation in joint_transform.h). A joint whose
// origin is its parent's (p = 0, e.g. the IRB 1600's wrist) skips the shift: the same values.
template <int Shape, bool kProject>
inline void AddInertiaAcrossShape(const Pose& X_AB, const Matrix6d& I_B, Matrix6d* I_A,
                                  const Vector6d* U = nullptr, double inv_D = 0.0) {
  if constexpr (Shape == kTranslatingJoint) {
    AddInertiaAcrossCoordinateJoint<-1, kProject>(1.0, 0.0, X_AB.p, I_B, I_A, U, inv_D);
  } else {
    constexpr int i = (Shape + 1) % 3, j = (Shape + 2) % 3;
    const double c = X_AB.R(i, i), s = X_AB.R(j, i);
    if (X_AB.p.x() == 0.0 && X_AB.p.y() == 0.0 && X_AB.p.z() == 0.0) {
      AddInertiaAcrossCoordinateJoint<Shape, kProject, false>(c, s, X_AB.p, I_B, I_A, U, inv_D);
    } else {
      AddInertiaAcrossCoordinateJoint<Shape, kProject>(c, s, X_AB.p, I_B, I_A, U, inv_D);
    }
  }
}

}  // namespace internal

// I_A += X_AB^T I_B X_AB for X_AB = JointTransform(joint, q) and Shape = JointShape(joint)
// (joint_spatial_transform.h), I_B a symmetric spatial (or articulated-body) inertia. The
// fast paths (Shape >= kTranslatingJoint) read only the upper triangles of I_B's diagonal
// blocks and its top-right block; kGeneralJoint reads all of it.
template <int Shape>
inline void AddInertiaAcross(const Pose& X_AB, const Matrix6d& I_B, Matrix6d* I_A) {
  if constexpr (Shape == kGeneralJoint) {
    AddInertiaToParent(X_AB, I_B, I_A);
  } else {
    internal::AddInertiaAcrossShape<Shape, false>(X_AB, I_B, I_A);
  }
}

// The articulated-body algorithm's step to the parent: I_A += X_AB^T (I_B - U U^T / D) X_AB,
// inv_D = 1 / D. Leaves I_B unchanged on the fast paths; kGeneralJoint projects it in place.
template <int Shape>
inline void AddProjectedInertiaAcross(const Pose& X_AB, Matrix6d& I_B, const Vector6d& U,
                                      double inv_D, Matrix6d* I_A) {
  if constexpr (Shape == kGeneralJoint) {
    I_B.noalias() -= (U * inv_D) * U.transpose();
    AddInertiaToParent(X_AB, I_B, I_A);
  } else {
    internal::AddInertiaAcrossShape<Shape, true>(X_AB, I_B, I_A, &U, inv_D);
  }
}

// The same, dispatching on the joint's shape at run time.
inline void AddInertiaAcrossJoint(const Joint& joint, const Pose& X_AB, const Matrix6d& I_B,
                                  Matrix6d* I_A) {
  DispatchJointShape(joint, [&](auto shape) { AddInertiaAcross<shape()>(X_AB, I_B, I_A); });
}

}  // namespace mbstream

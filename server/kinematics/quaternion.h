// Unit quaternions (qw, qx, qy, qz), scalar first, as the free and ball joints keep their
// rotations (model.h): the rotation matrix, the rate 1/2 quat (x) (0, w) of an angular velocity
// w in the rotated (child) frame, and the normalisation the integrators project with. Inline,
// allocate nothing.
#pragma once

#include <cmath>

#include "server/math/spatial.h"

namespace mbstream::quaternion {

// The rotation of quat[0..3], normalised first (a quaternion that drifted from unit length
// still gives a rotation).
inline Matrix3d Rotation(const double* quat) {
  const double w = quat[0], x = quat[1], y = quat[2], z = quat[3];
  const double s = 2.0 / (w * w + x * x + y * y + z * z);
  const double xx = s * x * x, yy = s * y * y, zz = s * z * z;
  const double xy = s * x * y, xz = s * x * z, yz = s * y * z;
  const double wx = s * w * x, wy = s * w * y, wz = s * w * z;
  Matrix3d R;
  R << 1.0 - (yy + zz), xy - wz, xz + wy,  //
      xy + wz, 1.0 - (xx + zz), yz - wx,   //
      xz - wy, yz + wx, 1.0 - (xx + yy);
  return R;
}

// quat' = 1/2 quat (x) (0, w) (4 values) for the angular velocity w (3 values) in the rotated
// frame.
inline void Rate(const double* quat, const double* w_B, double* rate) {
  const double w = quat[0], x = quat[1], y = quat[2], z = quat[3];
  const double a = w_B[0], b = w_B[1], c = w_B[2];
  rate[0] = 0.5 * (-x * a - y * b - z * c);
  rate[1] = 0.5 * (w * a + y * c - z * b);
  rate[2] = 0.5 * (w * b + z * a - x * c);
  rate[3] = 0.5 * (w * c + x * b - y * a);
}

// Scales quat[0..3] to unit length; returns its norm before.
inline double Normalise(double* quat) {
  const double norm =
      std::sqrt(quat[0] * quat[0] + quat[1] * quat[1] + quat[2] * quat[2] + quat[3] * quat[3]);
  for (int k = 0; k < 4; ++k) quat[k] /= norm;
  return norm;
}

}  // namespace mbstream::quaternion

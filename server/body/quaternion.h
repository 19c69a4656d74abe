// Unit quaternions e = (e0, e1, e2, e3), scalar first, for body orientations: R(e) maps body
// coordinates to base coordinates. The state keeps e unnormalised (the integrator moves it
// off the unit sphere by its local errors); every rotation is taken from e / |e|, and the
// norm's drift is measured (BodyReadout), not corrected.
#pragma once

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "server/math/spatial.h"

namespace mbstream {

using Vector4d = Eigen::Vector4d;

// R(e / |e|). Allocates nothing.
inline Matrix3d QuaternionRotation(const Vector4d& e) {
  const Vector4d u = e / e.norm();
  const double w = u(0), x = u(1), y = u(2), z = u(3);
  Matrix3d r;
  r << 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),  //
      2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),   //
      2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y);
  return r;
}

// de/dt = 1/2 e (x) (0, w) for the angular velocity w in body coordinates (rad/s). It keeps
// |e| constant exactly; only integration errors change it.
inline Vector4d QuaternionRate(const Vector4d& e, const Vector3d& w) {
  const Vector3d ev = e.tail<3>();
  Vector4d rate;
  rate(0) = -0.5 * ev.dot(w);
  rate.tail<3>() = 0.5 * (e(0) * w + ev.cross(w));
  return rate;
}

// The unit quaternion of a rotation matrix, with e0 >= 0.
inline Vector4d QuaternionFromRotation(const Matrix3d& R) {
  Eigen::Quaterniond q(R);
  q.normalize();
  Vector4d e(q.w(), q.x(), q.y(), q.z());
  if (e(0) < 0.0) e = -e;
  return e;
}

}  // namespace mbstream

// Inertia of a rigid body: mass, centre of mass and rotational inertia about the centre
// of mass, all in the body's frame.
#pragma once

#include "server/math/spatial.h"

namespace mbstream {

struct RigidInertia {
  double mass = 0.0;                        // kg
  Vector3d com = Vector3d::Zero();          // p_BoBcm_B, m
  Matrix3d inertia_com = Matrix3d::Zero();  // I_Bcm_B, kg*m^2, about the centre of mass

  // Spatial inertia about Bo in B: [[I_cm - m [c]x^2, m [c]x], [m [c]x^T, m 1]].
  Matrix6d ToMatrix() const {
    Matrix6d m6;
    const Matrix3d C = Skew(com);
    m6.topLeftCorner<3, 3>() = inertia_com - mass * C * C;
    m6.topRightCorner<3, 3>() = mass * C;
    m6.bottomLeftCorner<3, 3>() = mass * C.transpose();
    m6.bottomRightCorner<3, 3>() = mass * Matrix3d::Identity();
    return m6;
  }

  // I * m for a motion vector m = [w; v_Bo]: the body's spatial momentum about Bo.
  [[gnu::always_inline]] Vector6d Apply(const Vector6d& m) const {
    const Vector3d w = m.head<3>();
    const Vector3d p = mass * (m.tail<3>() + w.cross(com));  // linear momentum
    Vector6d h;
    h.head<3>().noalias() = inertia_com * w;
    h.head<3>() += com.cross(p);
    h.tail<3>() = p;
    return h;
  }

  // The same body seen from frame A, given X_AB.
  RigidInertia ExpressedIn(const Pose& X_AB) const {
    return RigidInertia{mass, X_AB.Apply(com), X_AB.R * inertia_com * X_AB.R.transpose()};
  }

  // The inertia of two bodies rigidly joined, both given in the same frame.
  RigidInertia CombinedWith(const RigidInertia& other) const {
    const double m = mass + other.mass;
    if (m <= 0.0) return RigidInertia{};
    const Vector3d c = (mass * com + other.mass * other.com) / m;
    auto shifted = [&c](const RigidInertia& b) {
      const Vector3d d = b.com - c;
      return Matrix3d(b.inertia_com +
                      b.mass * (d.squaredNorm() * Matrix3d::Identity() - d * d.transpose()));
    };
    return RigidInertia{m, c, shifted(*this) + shifted(other)};
  }
};

}  // namespace mbstream

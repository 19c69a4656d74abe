// Spatial vector algebra (Featherstone, "Rigid Body Dynamics Algorithms", ch. 2).
//
// Conventions used throughout mbstream's physics:
// - A motion vector is [angular; linear] = [w; v_O]: angular velocity and the velocity of
//   the frame's origin O, both expressed in that frame's coordinates (rad/s, m/s).
// - A force vector is [moment about O; force] = [n_O; f] (N*m, N).
// - Pose X_AB = {R_AB, p_AoBo_A}: orientation of frame B in A and position of B's origin
//   measured from A's origin, expressed in A (m). All functions are inline and allocate
//   nothing.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace mbstream {

using Vector3d = Eigen::Vector3d;
using Matrix3d = Eigen::Matrix3d;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Matrix63d = Eigen::Matrix<double, 6, 3>;

// Pose of frame B in frame A: R_AB and p_AoBo_A.
struct Pose {
  Matrix3d R = Matrix3d::Identity();
  Vector3d p = Vector3d::Zero();

  static Pose Identity() { return Pose{}; }

  // X_AC = X_AB * X_BC.
  Pose operator*(const Pose& X_BC) const { return Pose{R * X_BC.R, R * X_BC.p + p}; }

  // p_Ao_Q_A for a point Q given as p_Bo_Q_B.
  Vector3d Apply(const Vector3d& p_BQ) const { return R * p_BQ + p; }

  // X_BA.
  Pose Inverse() const { return Pose{R.transpose(), -(R.transpose() * p)}; }
};

// The matrix [v]x with [v]x u = v x u.
inline Matrix3d Skew(const Vector3d& v) {
  Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// Rotation by `angle` (rad) about the unit vector `axis` (Rodrigues' formula).
inline Matrix3d AxisAngleRotation(const Vector3d& axis, double angle) {
  const double s = std::sin(angle);
  const double c = std::cos(angle);
  const double t = 1.0 - c;
  const double x = axis.x(), y = axis.y(), z = axis.z();
  Matrix3d r;
  r << t * x * x + c, t * x * y - s * z, t * x * z + s * y,  //
      t * x * y + s * z, t * y * y + c, t * y * z - s * x,   //
      t * x * z - s * y, t * y * z + s * x, t * z * z + c;
  return r;
}

// Motion vector m_A (of a body, expressed in A at Ao) re-expressed in child frame B at Bo.
inline Vector6d MotionToChild(const Pose& X_AB, const Vector6d& m_A) {
  Vector6d m_B;
  const Vector3d w = m_A.head<3>();
  m_B.head<3>().noalias() = X_AB.R.transpose() * w;
  m_B.tail<3>().noalias() = X_AB.R.transpose() * (m_A.tail<3>() + w.cross(X_AB.p));
  return m_B;
}

// Force vector f_B (expressed in B, moment about Bo) re-expressed in parent frame A at Ao.
inline Vector6d ForceToParent(const Pose& X_AB, const Vector6d& f_B) {
  Vector6d f_A;
  f_A.tail<3>().noalias() = X_AB.R * f_B.tail<3>();
  f_A.head<3>().noalias() = X_AB.R * f_B.head<3>();
  f_A.head<3>() += X_AB.p.cross(f_A.tail<3>());
  return f_A;
}

// Motion cross product m1 x m2 (Featherstone's crm).
[[gnu::always_inline]] inline Vector6d CrossMotion(const Vector6d& m1, const Vector6d& m2) {
  Vector6d r;
  const Vector3d w = m1.head<3>(), v = m1.tail<3>();
  r.head<3>() = w.cross(m2.head<3>());
  r.tail<3>() = w.cross(m2.tail<3>()) + v.cross(m2.head<3>());
  return r;
}

// Force cross product m x* f (Featherstone's crf).
[[gnu::always_inline]] inline Vector6d CrossForce(const Vector6d& m, const Vector6d& f) {
  Vector6d r;
  const Vector3d w = m.head<3>(), v = m.tail<3>();
  r.head<3>() = w.cross(f.head<3>()) + v.cross(f.tail<3>());
  r.tail<3>() = w.cross(f.tail<3>());
  return r;
}

// Adds to I_A (a 6x6 spatial inertia in parent frame A at Ao) the inertia I_B given in child
// frame B at Bo: I_A += X^T I_B X, computed blockwise (no 6x6 products).
inline void AddInertiaToParent(const Pose& X_AB, const Matrix6d& I_B, Matrix6d* I_A) {
  const Matrix3d& R = X_AB.R;
  // Rotate the blocks into A's orientation (origin still at Bo).
  const Matrix3d A = R * I_B.topLeftCorner<3, 3>() * R.transpose();
  const Matrix3d B = R * I_B.topRightCorner<3, 3>() * R.transpose();
  const Matrix3d C = R * I_B.bottomRightCorner<3, 3>() * R.transpose();
  // Shift the reference point from Bo to Ao: with P = [p]x,
  // [[A, B], [B^T, C]] -> [[A + P B^T - B P - P C P, B + P C], [.., C]].
  const Matrix3d P = Skew(X_AB.p);
  const Matrix3d PC = P * C;
  const Matrix3d B2 = B + PC;
  I_A->topLeftCorner<3, 3>() += A + P * B.transpose() - B * P - PC * P;
  I_A->topRightCorner<3, 3>() += B2;
  I_A->bottomLeftCorner<3, 3>() += B2.transpose();
  I_A->bottomRightCorner<3, 3>() += C;
}

}  // namespace mbstream

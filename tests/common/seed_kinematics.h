// The seed's closed-form forward kinematics of the IRB 1600 (the lengths of the Device block
// of models/irb1600/irb1600.scene), written independently of the model code, as the
// reference of the tests.
#pragma once

#include <Eigen/Geometry>

namespace mbstream::testing {

// TCP (m, base frame) for joint angles q[0..5] (rad):
// Rz(q1) Tr(L2,0,L1) Ry(q2) Tr(0,0,L3) Ry(q3) Tr(L4,0,0) Rx(q4) Ry(q5) Rx(q6) Tr(L5,0,0).
inline Eigen::Vector3d SeedTcp(const double* q) {
  using Eigen::AngleAxisd;
  using Eigen::Translation3d;
  using Eigen::Vector3d;
  const Eigen::Isometry3d T =
      Eigen::Isometry3d(AngleAxisd(q[0], Vector3d::UnitZ())) * Translation3d(0.150, 0, 0.4865) *
      AngleAxisd(q[1], Vector3d::UnitY()) * Translation3d(0, 0, 0.475) *
      AngleAxisd(q[2], Vector3d::UnitY()) * Translation3d(0.600, 0, 0) *
      AngleAxisd(q[3], Vector3d::UnitX()) * AngleAxisd(q[4], Vector3d::UnitY()) *
      AngleAxisd(q[5], Vector3d::UnitX()) * Translation3d(0.065, 0, 0);
  return T.translation();
}

}  // namespace mbstream::testing

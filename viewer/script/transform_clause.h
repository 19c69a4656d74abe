// The transform clause of the script: `(Shift x X y Y z Z Euler E1 E2 E3)`.
//
// Every part is optional and `Shift` may be left out before the axis values. Lengths are
// millimetres, angles degrees. The frame it describes is first rotated by ZYZ Euler angles
// (intrinsic: Rz(e1) Ry(e2) Rz(e3)) about the common origin, then shifted:
// T = Trans(shift) * Rz(e1) * Ry(e2) * Rz(e3).
#pragma once

#include <Eigen/Geometry>

#include "viewer/script/source_position.h"

namespace mbstream::scene_script {

struct TransformClause {
  SourcePosition position;  // of '(' when written, else where it would have been
  Eigen::Vector3d shift_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d euler_deg = Eigen::Vector3d::Zero();

  bool IsIdentity() const { return shift_mm.isZero(0) && euler_deg.isZero(0); }
  // The transform with lengths converted by `metres_per_unit` (0.001 for metres).
  Eigen::Isometry3d ToIsometry(double metres_per_unit) const;
};

// Rz(e1) Ry(e2) Rz(e3), angles in degrees.
Eigen::Matrix3d EulerZyzDegrees(const Eigen::Vector3d& euler_deg);

}  // namespace mbstream::scene_script

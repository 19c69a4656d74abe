#include "viewer/script/transform_clause.h"

#include <numbers>

namespace mbstream::scene_script {

Eigen::Matrix3d EulerZyzDegrees(const Eigen::Vector3d& euler_deg) {
  const Eigen::Vector3d rad = euler_deg * (std::numbers::pi / 180.0);
  return (Eigen::AngleAxisd(rad[0], Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(rad[1], Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rad[2], Eigen::Vector3d::UnitZ()))
      .toRotationMatrix();
}

Eigen::Isometry3d TransformClause::ToIsometry(double metres_per_unit) const {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = EulerZyzDegrees(euler_deg);
  t.translation() = shift_mm * metres_per_unit;
  return t;
}

}  // namespace mbstream::scene_script

#include "viewer/model/inertia_box.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace mbstream::viewer {

InertiaBox BoxOfInertia(double mass, const Eigen::Matrix3d& inertia,
                        const Eigen::Isometry3d& com_pose, double min_edge) {
  InertiaBox box;
  box.pose = com_pose;
  if (!(mass > 0) || !inertia.allFinite()) return box;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(0.5 *
                                                              (inertia + inertia.transpose()));
  if (solver.info() != Eigen::Success) return box;
  const Eigen::Vector3d moments = solver.eigenvalues();
  Eigen::Matrix3d axes = solver.eigenvectors();
  if (axes.determinant() < 0) axes.col(2) = -axes.col(2);
  // I_x = m (b^2 + c^2) / 12, ...: a^2 = 6 (I_y + I_z - I_x) / m.
  for (int i = 0; i < 3; ++i) {
    const double square = 6 * (moments.sum() - 2 * moments[i]) / mass;
    box.size[i] = std::max(std::sqrt(std::max(square, 0.0)), min_edge);
  }
  box.pose.linear() = com_pose.linear() * axes;
  return box;
}

}  // namespace mbstream::viewer

// The box a link's inertia describes: the solid box of uniform density with the same mass
// and principal moments, for a placeholder where a mesh is missing.
#pragma once

#include <Eigen/Geometry>

namespace mbstream::viewer {

struct InertiaBox {
  Eigen::Vector3d size = Eigen::Vector3d::Constant(0.05);  // metres, edges along the axes
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // its centre and axes in the link
};

// `inertia` about the centre of mass `com_pose` (its frame), kg*m^2; `mass` kg. Edges are
// at least `min_edge`; a non-positive mass or an unphysical tensor gives the default cube
// at the centre of mass.
InertiaBox BoxOfInertia(double mass, const Eigen::Matrix3d& inertia,
                        const Eigen::Isometry3d& com_pose, double min_edge = 0.01);

}  // namespace mbstream::viewer

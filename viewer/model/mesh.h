// A polyhedral surface: points and polygonal faces (indices into points). Faces of the
// closed primitives are ordered anticlockwise seen from outside.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace mbstream::viewer {

struct Mesh {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::vector<int>> faces;
};

}  // namespace mbstream::viewer

// A bare primitive collision geometry, for the contact suites that call the law and the
// narrow phase directly.
#pragma once

#include <vector>

#include "server/model/collision_geometry.h"
#include "server/parse/convex_hull.h"

namespace mbstream::contact_testing {

// A primitive geometry of `type` (its other fields the defaults).
inline CollisionGeometry Primitive(ShapeType type, double radius, double length, Vector3d size) {
  CollisionGeometry g;
  g.shape.type = type;
  g.shape.radius = radius;
  g.shape.length = length;
  g.shape.size = size;
  return g;
}

// The convex hull (qhull) of a box of `size`, centred: as a collision mesh of a box is read,
// with a point inside that is not a hull vertex.
inline CollisionGeometry BoxHull(const Vector3d& size) {
  std::vector<Vector3d> corners;
  for (int k = 0; k < 8; ++k) {
    corners.push_back(
        Vector3d(k & 1 ? 0.5 : -0.5, k & 2 ? 0.5 : -0.5, k & 4 ? 0.5 : -0.5).cwiseProduct(size));
  }
  corners.emplace_back(0.0, 0.0, 0.0);
  CollisionGeometry g;
  g.shape.type = ShapeType::kConvex;
  g.shape.convex = ConvexHullOf(corners, "box hull");
  return g;
}

}  // namespace mbstream::contact_testing

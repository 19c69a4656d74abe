// A bare primitive collision geometry, for the contact suites that call the law and the
// narrow phase directly.
#pragma once

#include "server/model/collision_geometry.h"

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

}  // namespace mbstream::contact_testing

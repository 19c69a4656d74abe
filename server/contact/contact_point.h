// One point of contact between two collision geometries, as the narrow phase finds it and the
// contact law fills it (docs/contact.md). Every vector is in the world frame.
#pragma once

#include "server/math/spatial.h"

namespace mbstream {

struct ContactPoint {
  int geometry_a = 0, geometry_b = 0;   // indices into Model::collisions
  Vector3d point = Vector3d::Zero();    // m: midway between the two surfaces
  Vector3d normal = Vector3d::UnitZ();  // unit, from b toward a: the direction that pushes a off b
  double depth = 0.0;                   // m: the penetration (> 0 when the surfaces overlap)
  // The share of the pair's stiffness this point takes: its weight times its depth over the
  // sum over the pair's points (1 for a pair with one point; 1/4 each for a box resting flat).
  double share = 1.0;
  // How much the point stands for the surface (1 but for a cylinder's rim as it tilts:
  // narrow_phase.cc, RimCornerWeight).
  double weight = 1.0;
  double normal_force = 0.0;  // N, >= 0: the normal force on a (b gets the opposite)
  Vector3d friction_force = Vector3d::Zero();  // N: the friction force on a (b: the opposite)

  // A point x of one geometry `depth` below the other's face of outward normal n_face: the
  // point midway between the surfaces, the normal sign * n_face (+1 when the face is b's).
  static ContactPoint UnderFace(int a, int b, const Vector3d& x, const Vector3d& n_face,
                                double sign, double depth) {
    ContactPoint c;
    c.geometry_a = a;
    c.geometry_b = b;
    c.normal = sign * n_face;
    c.depth = depth;
    c.point = x + 0.5 * depth * n_face;
    return c;
  }
};

}  // namespace mbstream

// The collision geometry of a model, read from its <collision> elements (URDF and SDFormat):
// constant, shared by every run of the model, as the Model that holds it. No physics here:
// the contact forces are server/contact's (docs/contact.md).
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "server/math/spatial.h"

namespace mbstream {

// In the narrow phase's order (a pair is handled with its lesser type first).
enum class ShapeType { kSphere, kBox, kCylinder, kCapsule, kConvex, kPlane };

// A convex polytope: a collision mesh's convex hull, or one piece of it (server/parse/
// collision_meshes.h). Shared, as FCL's fcl::Convex shares them, by the Model and every run.
struct ConvexPolytope {
  std::shared_ptr<const std::vector<Vector3d>> vertices;  // in G (m), each a hull vertex
  // FCL's face list: for each face its vertex count (3: qhull's facets triangulated), then
  // its vertex indices, counter-clockwise seen from outside.
  std::shared_ptr<const std::vector<int>> faces;
  int num_faces = 0;
  double volume = 0.0;                                          // the hull's (m^3)
  Vector3d lower = Vector3d::Zero(), upper = Vector3d::Zero();  // its bounding box in G
};

// A shape in its geometry frame G.
struct CollisionShape {
  ShapeType type = ShapeType::kSphere;
  double radius = 0.0;               // sphere, cylinder, capsule (m)
  double length = 0.0;               // cylinder, capsule: along G's z, centred (m; a capsule's
                                     // cylinder part, the hemispheres beyond it)
  Vector3d size = Vector3d::Zero();  // box: full edge lengths along G's axes, centred (m)
  ConvexPolytope convex;             // convex: its vertices and faces
  // plane: through G's origin, normal G's z; the half-space below it (z < 0) is solid.
};

// What a model file says of a surface; NaN where it says nothing (the run spec's contact
// defaults then apply, server/contact/contact_settings.h).
struct SurfaceProperties {
  static constexpr double kUnset = std::numeric_limits<double>::quiet_NaN();
  double stiffness = kUnset;    // N/m: drake:point_contact_stiffness
  double dissipation = kUnset;  // s/m: drake:hunt_crossley_dissipation
  double mu_static = kUnset;    // drake:mu_static
  double mu_dynamic = kUnset;   // drake:mu_dynamic; SDFormat <surface><friction><ode><mu>
};

// Half the shape's smallest extent (m; a plane's: infinity): the size its penetration is
// measured against.
inline double ShapeHalfSize(const CollisionShape& s) {
  switch (s.type) {
    case ShapeType::kPlane:
      return std::numeric_limits<double>::infinity();
    case ShapeType::kBox:
      return 0.5 * s.size.minCoeff();
    case ShapeType::kConvex:
      return 0.5 * (s.convex.upper - s.convex.lower).minCoeff();
    case ShapeType::kSphere:
    case ShapeType::kCylinder:
    case ShapeType::kCapsule:
      return s.radius;
  }
  return s.radius;
}

struct CollisionGeometry {
  std::string name;   // the <collision>'s name ("" when it has none)
  std::string link;   // the link it belongs to (scoped in an SDFormat world)
  std::string where;  // "FILE:LINE" of the <collision>
  int piece = 0;      // a mesh's convex piece (0 for the first; one geometry per piece)
  int body = -1;      // the Model body that carries it, or kBase (-1) for the world
  Pose X_BG;          // its geometry frame G in that body's frame
  CollisionShape shape;
  SurfaceProperties surface;
  // SDFormat <surface><contact><collide_bitmask>: two geometries may touch only when their
  // masks share a bit. 0xffff (every bit) when not given, as SDFormat's default.
  uint16_t collide_bitmask = 0xffff;
};

}  // namespace mbstream

// A mesh's convex hull against every shape (issue 44, "Geometry and what collides";
// docs/contact.md): a 0.2 m cube given as a hull (qhull, server/parse/convex_hull.h) touches a
// sphere, a box, a cylinder, a capsule, a plane and another hull as the primitive 0.2 m box
// does, 1 mm deep, with the normal along z; and the heap allocations of one narrow-phase call
// for each pair (FCL's GJK/EPA through libccd, for a cylinder or capsule, allocates: counted and
// printed, not hidden).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "server/contact/narrow_phase.h"
#include "server/parse/convex_hull.h"
#include "shared/common/check.h"
#include "tests/common/allocation_counter.h"
#include "tests/server/contact/primitive_geometry.h"

namespace mbstream {
namespace {

using namespace contact_testing;

// The hull of a cube of edge `edge`, centred.
CollisionGeometry CubeHull(double edge) { return BoxHull(Vector3d::Constant(edge)); }

Pose At(double z) {
  Pose X;
  X.p = Vector3d(0.0, 0.0, z);
  return X;
}

TEST(HullPairsTest, ACubesHullIsItsCorners) {
  const CollisionGeometry cube = CubeHull(0.2);
  EXPECT_EQ(cube.shape.convex.vertices->size(), 8u);
  EXPECT_EQ(cube.shape.convex.num_faces, 12);  // six squares, triangulated
  EXPECT_NEAR(cube.shape.convex.volume, 0.008, 1e-15);
  EXPECT_EQ(cube.shape.convex.lower, Vector3d::Constant(-0.1));
  EXPECT_EQ(cube.shape.convex.upper, Vector3d::Constant(0.1));
  EXPECT_DOUBLE_EQ(ShapeHalfSize(cube.shape), 0.1);
}

TEST(HullPairsTest, FlatOrTooFewPointsAreRefusedByName) {
  const std::vector<Vector3d> flat = {Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0, 1, 0),
                                      Vector3d(1, 1, 0), Vector3d(0.5, 0.5, 0)};
  try {
    ConvexHullOf(flat, "robot.urdf:7: link 'a': collision 'c': mesh 'plate.stl'");
    FAIL() << "a flat mesh has no hull";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mesh 'plate.stl': its vertices span no volume"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(ConvexHullOf({Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0, 0, 1)}, "m"),
               InputError);
}

// Each shape 1 mm into the top face of the cube (hull, geometry 0; primitive box, 1), and the
// cube 1 mm into a plane: the same depth and normal from the hull as from the box.
TEST(HullPairsTest, TheHullTouchesEveryShapeAsTheBoxDoes) {
  const double d = 1e-3;
  std::vector<CollisionGeometry> g = {
      CubeHull(0.2),
      Primitive(ShapeType::kBox, 0, 0, Vector3d::Constant(0.2)),
      Primitive(ShapeType::kSphere, 0.05, 0, Vector3d::Zero()),
      Primitive(ShapeType::kBox, 0, 0, Vector3d::Constant(0.1)),
      Primitive(ShapeType::kCylinder, 0.05, 0.1, Vector3d::Zero()),
      Primitive(ShapeType::kCapsule, 0.05, 0.1, Vector3d::Zero()),
      CubeHull(0.1),
      Primitive(ShapeType::kPlane, 0, 0, Vector3d::Zero()),
  };
  struct Case {
    const char* name;
    int other;
    double z;  // the other shape's centre (the plane's level)
    long allocations = 0;
  };
  std::vector<Case> cases = {{"sphere", 2, 0.1 + 0.05 - d},   {"box", 3, 0.1 + 0.05 - d},
                             {"cylinder", 4, 0.1 + 0.05 - d}, {"capsule", 5, 0.1 + 0.1 - d},
                             {"hull", 6, 0.1 + 0.05 - d},     {"plane", 7, -0.1 + d}};
  NarrowPhase narrow(g);
  std::vector<ContactPoint> out;
  out.reserve(64);
  for (Case& c : cases) {
    const bool plane = c.other == 7;
    for (const int cube : {0, 1}) {
      out.clear();
      // warm the narrow phase's scratch, then count one call
      narrow.Collide(c.other, At(c.z), cube, Pose(), &out);
      out.clear();
      const long before = testing::AllocationCount();
      narrow.Collide(c.other, At(c.z), cube, Pose(), &out);
      if (cube == 0) c.allocations = testing::AllocationCount() - before;
      ASSERT_FALSE(out.empty()) << c.name << " against " << (cube == 0 ? "hull" : "box");
      for (const ContactPoint& p : out) {
        // normals from the cube (b) toward the other shape (a): +z, or -z for the plane below
        EXPECT_NEAR(p.normal.z(), plane ? -1.0 : 1.0, 1e-6) << c.name;
        EXPECT_NEAR(p.depth, d, 1e-6) << c.name << " against " << (cube == 0 ? "hull" : "box");
      }
      if (plane || c.other == 3 || c.other == 6) {
        EXPECT_EQ(out.size(), 4u);  // the face's four corners
      }
      if (c.other == 4) {
        EXPECT_EQ(out.size(), 16u);  // the standing cylinder's rim corners
      }
      if (c.other == 5) {
        EXPECT_EQ(out.size(), 1u);  // the capsule's end sphere
      }
      printf("RESULT %s against the %s: %zu point(s), depth %.9g\n", c.name,
             cube == 0 ? "hull" : "box", out.size(), out.front().depth);
    }
  }
  for (const Case& c : cases) {
    printf("RESULT allocations of one %s-hull call: %ld\n", c.name, c.allocations);
  }
  // Against a plane (the hull's vertices), a sphere (the nearest face or triangle point), a box
  // or a hull (vertices inside), a cylinder or capsule (under the face of least overlap) the
  // pairs are in closed form: no allocation (before FaceContacts the cylinder's and capsule's
  // went through libccd: 8 and 13).
  for (const Case& c : cases) EXPECT_EQ(c.allocations, 0) << c.name;
  // Apart: no contact, and the signed distance to the plane is exact.
  out.clear();
  narrow.Collide(2, At(0.3), 0, Pose(), &out);
  EXPECT_TRUE(out.empty());
  EXPECT_NEAR(narrow.SignedDistance(0, At(0.15), 7, Pose(), 1.0), 0.05, 1e-15);
}

// A sphere whose centre is inside the hull (the nearest face) or beyond an edge (the nearest
// point of the edge): exact, as FCL's sphere-box routine for the primitive box.
TEST(HullPairsTest, SphereAgainstTheHullIsExactInsideAndAtAnEdge) {
  std::vector<CollisionGeometry> g = {CubeHull(0.2),
                                      Primitive(ShapeType::kBox, 0, 0, Vector3d::Constant(0.2)),
                                      Primitive(ShapeType::kSphere, 0.05, 0, Vector3d::Zero())};
  NarrowPhase narrow(g);
  std::vector<ContactPoint> out;
  out.reserve(8);
  narrow.Collide(2, At(0.09), 0, Pose(), &out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].depth, 0.06, 1e-15);
  EXPECT_NEAR(out[0].normal.z(), 1.0, 1e-15);
  Pose edge;
  edge.p = Vector3d(0.12, 0.0, 0.12);
  for (const int cube : {0, 1}) {
    out.clear();
    narrow.Collide(2, edge, cube, Pose(), &out);
    ASSERT_EQ(out.size(), 1u) << cube;
    EXPECT_NEAR(out[0].depth, 0.05 - 0.02 * std::sqrt(2.0), 1e-12) << cube;
    EXPECT_NEAR(out[0].normal.x(), std::sqrt(0.5), 1e-12) << cube;
    EXPECT_NEAR(out[0].normal.z(), std::sqrt(0.5), 1e-12) << cube;
  }
  EXPECT_NEAR(narrow.SignedDistance(2, edge, 0, Pose(), 1.0), 0.02 * std::sqrt(2.0) - 0.05, 1e-15);
  EXPECT_NEAR(narrow.SignedDistance(2, At(0.3), 0, Pose(), 1.0), 0.15, 1e-15);
}

}  // namespace
}  // namespace mbstream

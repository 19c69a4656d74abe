// The contact law's pieces (server/contact/contact_law.h) against Drake's definitions, and the
// narrow phase's points and normals (server/contact/narrow_phase.h) for each kind of pair.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "server/contact/contact_law.h"
#include "server/contact/narrow_phase.h"
#include "tests/server/contact/primitive_geometry.h"

namespace mbstream {
namespace {

using namespace contact_testing;

namespace law = contact_law;

TEST(ContactLawTest, StribeckFollowsDrakesPiecewiseStep) {
  const double mu_s = 0.8, mu_d = 0.5, v_s = 1e-3;
  EXPECT_EQ(law::StribeckMu(0.0, mu_s, mu_d, v_s), 0.0);
  EXPECT_NEAR(law::StribeckMu(0.5 * v_s, mu_s, mu_d, v_s), mu_s * 0.5, 1e-15);  // step5(1/2)
  EXPECT_NEAR(law::StribeckMu(v_s, mu_s, mu_d, v_s), mu_s, 1e-15);
  EXPECT_NEAR(law::StribeckMu(2.0 * v_s, mu_s, mu_d, v_s), 0.5 * (mu_s + mu_d), 1e-15);
  EXPECT_EQ(law::StribeckMu(3.0 * v_s, mu_s, mu_d, v_s), mu_d);
  EXPECT_EQ(law::StribeckMu(1.0, mu_s, mu_d, v_s), mu_d);
  // Continuous at the joins.
  EXPECT_NEAR(law::StribeckMu(v_s * (1 - 1e-9), mu_s, mu_d, v_s),
              law::StribeckMu(v_s * (1 + 1e-9), mu_s, mu_d, v_s), 1e-8);
}

TEST(ContactLawTest, CombinationAndNormalForce) {
  EXPECT_DOUBLE_EQ(law::CombineStiffness(1e5, 1e5), 5e4);
  EXPECT_DOUBLE_EQ(law::CombineStiffness(1e5, 3e5), 7.5e4);
  EXPECT_DOUBLE_EQ(law::CombineDissipation(1e5, 1.0, 3e5, 2.0), (3e5 * 1.0 + 1e5 * 2.0) / 4e5);
  EXPECT_DOUBLE_EQ(law::CombineFriction(0.5, 0.5), 0.5);
  EXPECT_DOUBLE_EQ(law::CombineFriction(0.2, 0.6), 0.3);
  EXPECT_DOUBLE_EQ(law::NormalForce(1e4, 0.5, 1e-3, 2.0), 1e4 * 1e-3 * 2.0);
  EXPECT_EQ(law::NormalForce(1e4, 0.5, 1e-3, -3.0), 0.0);  // separating fast: clamped
}

Pose At(double x, double y, double z) {
  Pose X;
  X.p = Vector3d(x, y, z);
  return X;
}

TEST(NarrowPhaseTest, PointsAndNormalsFromBTowardA) {
  const std::vector<CollisionGeometry> g = {
      Primitive(ShapeType::kPlane, 0, 0, Vector3d::Zero()),         // 0
      Primitive(ShapeType::kSphere, 0.1, 0, Vector3d::Zero()),      // 1
      Primitive(ShapeType::kBox, 0, 0, Vector3d(0.2, 0.4, 0.2)),    // 2
      Primitive(ShapeType::kSphere, 0.2, 0, Vector3d::Zero()),      // 3
      Primitive(ShapeType::kCapsule, 0.05, 0.4, Vector3d::Zero()),  // 4
      Primitive(ShapeType::kCylinder, 0.1, 0.3, Vector3d::Zero()),  // 5
  };
  NarrowPhase narrow(g);
  std::vector<ContactPoint> out;
  // A sphere 1 mm into the plane: one point, normal up (plane toward sphere).
  narrow.Collide(1, At(0, 0, 0.099), 0, Pose(), &out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].geometry_a, 1);
  EXPECT_NEAR(out[0].depth, 1e-3, 1e-15);
  EXPECT_LT((out[0].normal - Vector3d::UnitZ()).norm(), 1e-15);
  EXPECT_LT((out[0].point - Vector3d(0, 0, -0.0005)).norm(), 1e-15);
  // The same pair the other way round: the normal from the sphere toward the plane.
  out.clear();
  narrow.Collide(0, Pose(), 1, At(0, 0, 0.099), &out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].geometry_a, 0);
  EXPECT_LT((out[0].normal + Vector3d::UnitZ()).norm(), 1e-15);
  // A box flat 2 mm into the plane: its four bottom corners.
  out.clear();
  narrow.Collide(2, At(0, 0, 0.098), 0, Pose(), &out);
  ASSERT_EQ(out.size(), 4u);
  for (const ContactPoint& c : out) EXPECT_NEAR(c.depth, 2e-3, 1e-15);
  // A capsule lying flat: its two end spheres; a cylinder standing: four rim points per end.
  out.clear();
  Pose flat = At(0, 0, 0.049);
  flat.R = AxisAngleRotation(Vector3d::UnitY(), M_PI / 2);
  narrow.Collide(4, flat, 0, Pose(), &out);
  EXPECT_EQ(out.size(), 2u);
  out.clear();
  narrow.Collide(5, At(0, 0, 0.149), 0, Pose(), &out);
  EXPECT_EQ(out.size(), 4u);
  // Two spheres 1 cm into each other along x: the normal from b (at x = 0) toward a.
  out.clear();
  narrow.Collide(1, At(0.29, 0, 0), 3, Pose(), &out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].depth, 0.01, 1e-12);
  EXPECT_LT((out[0].normal - Vector3d::UnitX()).norm(), 1e-12);
  // A sphere on a box's top face (FCL's routine): normal up, from the box toward the sphere.
  out.clear();
  narrow.Collide(1, At(0, 0, 0.195), 2, Pose(), &out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].depth, 0.005, 1e-12);
  EXPECT_LT((out[0].normal - Vector3d::UnitZ()).norm(), 1e-12);
  out.clear();
  narrow.Collide(2, Pose(), 1, At(0, 0, 0.195), &out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_LT((out[0].normal + Vector3d::UnitZ()).norm(), 1e-12);
  // A box on a box (FCL's box-box): normals up, from the lower toward the upper.
  out.clear();
  narrow.Collide(2, At(0, 0, 0.199), 2, Pose(), &out);
  ASSERT_FALSE(out.empty());
  for (const ContactPoint& c : out) {
    EXPECT_NEAR(c.depth, 1e-3, 1e-9);
    EXPECT_LT((c.normal - Vector3d::UnitZ()).norm(), 1e-9);
  }
  // Signed distances: 1 cm above the plane; overlapping spheres.
  EXPECT_NEAR(narrow.SignedDistance(1, At(0, 0, 0.11), 0, Pose(), 1.0), 0.01, 1e-15);
  EXPECT_NEAR(narrow.SignedDistance(1, At(0.29, 0, 0), 3, Pose(), 1.0), -0.01, 1e-12);
}

}  // namespace
}  // namespace mbstream

// The contact law's pieces (server/contact/contact_law.h) against Drake's definitions, and the
// narrow phase's points and normals (server/contact/narrow_phase.h) for each kind of pair.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
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
  // A capsule lying flat: its two end spheres; a cylinder standing: its lower rim's 16 corners.
  out.clear();
  Pose flat = At(0, 0, 0.049);
  flat.R = AxisAngleRotation(Vector3d::UnitY(), M_PI / 2);
  narrow.Collide(4, flat, 0, Pose(), &out);
  EXPECT_EQ(out.size(), 2u);
  out.clear();
  narrow.Collide(5, At(0, 0, 0.149), 0, Pose(), &out);
  EXPECT_EQ(out.size(), 16u);
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

// A can on a can, cap on cap (NarrowPhase::CapContacts): the upper rim clipped to the lower
// cap's, each corner a point with the normal along the axes. Centred equal cans: the 16 corners
// of the rims' polygon, each 0.1 mm deep; 1 cm off the axis: the lens of the two rims, its
// points inside both; their spring's moment about the lower axis continuous as the upper can
// slides across 1 mm (the polytopes' Lipschitz check of polytope_pairs_test, for rims).
TEST(ContactLawTest, ACanOnACanStandsOnTheOverlapOfTheirRims) {
  std::vector<CollisionGeometry> cans = {
      Primitive(ShapeType::kCylinder, 0.05, 0.15, Vector3d::Zero()),
      Primitive(ShapeType::kCylinder, 0.05, 0.15, Vector3d::Zero())};
  NarrowPhase narrow(cans);
  const auto collide = [&](double x, double yaw) {
    Pose upper = At(x, 0, 0.15 - 1e-4);
    upper.R = AxisAngleRotation(Vector3d::UnitZ(), yaw);
    std::vector<ContactPoint> out;
    narrow.Collide(1, upper, 0, Pose(), &out);
    return out;
  };
  const std::vector<ContactPoint> centred = collide(0.0, 0.0);
  EXPECT_GE(centred.size(), 16u);
  for (const ContactPoint& c : centred) {
    EXPECT_NEAR(c.depth, 1e-4, 1e-12);
    EXPECT_LT((c.normal - Vector3d::UnitZ()).norm(), 1e-12);  // from the lower can up
    EXPECT_NEAR(c.point.z(), 0.075 - 0.5e-4, 1e-12);
    EXPECT_LE(std::hypot(c.point.x(), c.point.y()), 0.05 + 1e-12);
  }
  for (const double yaw : {0.0, 0.3}) {
    const std::vector<ContactPoint> lens = collide(0.01, yaw);
    ASSERT_GE(lens.size(), 3u) << yaw;
    for (const ContactPoint& c : lens) {
      EXPECT_LE(std::hypot(c.point.x(), c.point.y()), 0.05 + 1e-12) << yaw;
      EXPECT_LE(std::hypot(c.point.x() - 0.01, c.point.y()), 0.05 + 1e-12) << yaw;
    }
  }
  // The moment about the lower can's axis (y component) of k depth at each point, sliding.
  double previous = 0.0, jump = 0.0;
  for (int step = 0; step <= 1000; ++step) {
    const std::vector<ContactPoint> out = collide(0.01 + 1e-6 * step, 0.3);
    double sum = 0.0, moment = 0.0;
    for (const ContactPoint& c : out) sum += c.depth;
    for (const ContactPoint& c : out) moment += c.depth / sum * c.depth * c.point.x();
    if (step > 0) jump = std::max(jump, std::abs(moment - previous));
    previous = moment;
  }
  printf("RESULT largest change of the moment per micrometre %.3g (of %.3g)\n", jump, previous);
  EXPECT_LT(jump, 1e-3 * std::abs(previous));
}

// A can on a plane as it tilts from standing to 0.5 rad, its lowest rim point 0.1 mm deep: the
// spring's force and moment (each point's share of k times its depth) change continuously, from
// the rim's corners standing to its exact deepest point leaning (RimCornerWeight). Before, the
// points switched from four to one at 1e-9 rad: the moment jumped by the force times the radius.
TEST(ContactLawTest, ACanTiltingOnAPlaneKeepsItsWrenchContinuous) {
  const std::vector<CollisionGeometry> shapes = {
      Primitive(ShapeType::kPlane, 0, 0, Vector3d::Zero()),
      Primitive(ShapeType::kCylinder, 0.05, 0.15, Vector3d::Zero())};
  NarrowPhase narrow(shapes);
  const double depth = 1e-4;
  double previous_force = 0.0, previous_moment = 0.0, force_jump = 0.0, moment_jump = 0.0;
  for (int step = 0; step <= 5000; ++step) {
    const double tilt = 1e-4 * step;
    Pose can;
    can.R = AxisAngleRotation(Vector3d::UnitY(), tilt);
    // the lowest rim point (the lower cap's, toward -x) at z = -depth
    can.p = Vector3d(0, 0, 0.075 * std::cos(tilt) + 0.05 * std::sin(tilt) - depth);
    std::vector<ContactPoint> out;
    narrow.Collide(1, can, 0, Pose(), &out);
    ASSERT_FALSE(out.empty()) << tilt;
    double sum = 0.0, force = 0.0, moment = 0.0;
    for (const ContactPoint& c : out) sum += c.weight * c.depth;
    for (const ContactPoint& c : out) {
      const double f = c.weight * c.depth / sum * c.depth;
      force += f;
      moment += f * (c.point.x() - can.p.x());
    }
    if (step > 0) {
      force_jump = std::max(force_jump, std::abs(force - previous_force));
      moment_jump = std::max(moment_jump, std::abs(moment - previous_moment));
    }
    previous_force = force;
    previous_moment = moment;
  }
  printf("RESULT largest change per 1e-4 rad: force %.3g m (of %.3g), moment %.3g m^2\n",
         force_jump, depth, moment_jump);
  // Each corner's depth moves by at most 2 R (1e-4 rad) = 1e-5 m a step: the force and the
  // moment change by about that (measured 4.9e-6 m and 2.5e-7 m^2). The old switch moved the
  // moment by depth R = 5e-6 m^2 at once.
  EXPECT_LT(force_jump, 1e-5);
  EXPECT_LT(moment_jump, 0.1 * depth * 0.05);
}

}  // namespace
}  // namespace mbstream

// A box resting on a box (server/contact/narrow_phase.h, FCL's boxBox2): the contact set is the
// whole clipped polygon of the two faces, so that the contact force is a continuous function of
// the pose. Culled to four points (FCL's and ODE's default), which four are kept jumps as the
// upper box tilts, and BDF's Newton iteration failed at every step on a turned box stacked off
// centre (30,000 steps to t = 0.1 s; docs/contact.md).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "server/contact/narrow_phase.h"
#include "tests/server/contact/primitive_geometry.h"

namespace mbstream {
namespace {

using namespace contact_testing;

constexpr double kSide = 0.1;  // m, both cubes

// The upper cube turned by `yaw` about z, tilted by `tilt` about x, its centre 1 cm to the side
// and `sink` below resting height on the lower cube (at the origin).
Pose Upper(double yaw, double tilt, double sink) {
  Pose X;
  X.R = AxisAngleRotation(Vector3d::UnitZ(), yaw) * AxisAngleRotation(Vector3d::UnitX(), tilt);
  X.p = Vector3d(0.01, 0.0, kSide - sink);
  return X;
}

// The spring part of the contact wrench about the origin, per unit stiffness: sum of depth *
// normal and of point x (depth * normal) (m and m^2).
struct Wrench {
  Vector3d force = Vector3d::Zero();
  Vector3d moment = Vector3d::Zero();
};

Wrench SpringWrench(const std::vector<ContactPoint>& points) {
  Wrench w;
  for (const ContactPoint& c : points) {
    w.force += c.depth * c.normal;
    w.moment += c.point.cross(c.depth * c.normal);
  }
  return w;
}

class BoxBoxTest : public ::testing::Test {
 protected:
  std::vector<ContactPoint> Collide(const Pose& upper) {
    std::vector<ContactPoint> out;
    narrow_.Collide(1, upper, 0, Pose(), &out);
    return out;
  }

  const std::vector<CollisionGeometry> geometries_ = {
      Primitive(ShapeType::kBox, 0, 0, Vector3d::Constant(kSide)),
      Primitive(ShapeType::kBox, 0, 0, Vector3d::Constant(kSide)),
  };
  NarrowPhase narrow_{geometries_};
};

TEST_F(BoxBoxTest, ATurnedBoxStandsOnTheWholeOverlapOfTheTwoFaces) {
  // Turned 0.3 rad and 1 cm off: neither square holds a corner of the other, so the overlap is
  // an octagon, each corner an edge of one crossing an edge of the other.
  const std::vector<ContactPoint> points = Collide(Upper(0.3, 0.0, 1e-4));
  ASSERT_EQ(points.size(), 8u);
  for (const ContactPoint& c : points) {
    EXPECT_NEAR(c.depth, 1e-4, 1e-12);
    EXPECT_LT((c.normal - Vector3d::UnitZ()).norm(), 1e-12);
    // On the boundary of the lower face or of the upper one (in its own frame).
    const Vector3d p = c.point;
    const Vector3d u = Upper(0.3, 0.0, 1e-4).R.transpose() * (p - Upper(0.3, 0.0, 1e-4).p);
    const double lower_edge = std::max(std::abs(p.x()), std::abs(p.y()));
    const double upper_edge = std::max(std::abs(u.x()), std::abs(u.y()));
    EXPECT_LE(lower_edge, 0.5 * kSide + 1e-12);
    EXPECT_LE(upper_edge, 0.5 * kSide + 1e-12);
    EXPECT_TRUE(std::abs(lower_edge - 0.5 * kSide) < 1e-9 ||
                std::abs(upper_edge - 0.5 * kSide) < 1e-9)
        << p.transpose();
  }
  // Flat and evenly sunk: the spring force is depth times the overlap's corners (8), up.
  const Wrench w = SpringWrench(points);
  EXPECT_NEAR(w.force.z(), 8e-4, 1e-12);
}

TEST_F(BoxBoxTest, TheContactWrenchIsContinuousAsTheUpperBoxTilts) {
  // Tilted through -2..2 mrad in 1e-5 rad steps. Each point's depth changes by at most its
  // distance from the upper centre (< 0.09 m) times the step, and a point enters or leaves at
  // depth 0: the force sum over at most 8 points changes by at most 8 * 0.09 * step per step.
  // Each point's moment, depth (< 4e-4 m) times its lever in the faces (< 0.08 m), changes by
  // at most 0.09 step * 0.08 + 4e-4 * 0.1 step (the point moves) < 0.01 step. A point of depth
  // ~2e-4 m dropped or taken in (culling) is ten times these bounds or more.
  const double step = 1e-5;
  for (const double yaw : {0.0, 0.3, 0.7}) {
    Wrench previous = SpringWrench(Collide(Upper(yaw, -2e-3, 2e-4)));
    double worst_force = 0.0, worst_moment = 0.0;
    for (int k = 1; k <= 400; ++k) {
      const Wrench w = SpringWrench(Collide(Upper(yaw, -2e-3 + k * step, 2e-4)));
      worst_force = std::max(worst_force, (w.force - previous.force).norm());
      worst_moment = std::max(worst_moment, (w.moment - previous.moment).norm());
      previous = w;
    }
    EXPECT_LE(worst_force, 8 * 0.09 * step) << "yaw " << yaw;
    EXPECT_LE(worst_moment, 8 * 0.01 * step) << "yaw " << yaw;
  }
}

}  // namespace
}  // namespace mbstream

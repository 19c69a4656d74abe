// A box or a mesh's hull resting on a box or a hull (server/contact/narrow_phase.h: FCL's
// boxBox2 for two boxes, server/contact/polytope_clip.h for a hull): the contact set is the
// whole clipped polygon of the two faces, so that the contact force is a continuous function of
// the pose. Culled to four points (FCL's and ODE's default), which four are kept jumps as the
// upper box tilts, and BDF's Newton iteration failed at every step on a turned box stacked off
// centre (30,000 steps to t = 0.1 s); a hull's one GJK/EPA point did the same (50,000 steps to
// t = 0.03 s; docs/contact.md). And the signed distance of two polytopes, the root function
// that finds a contact's start: exact for faces and for crossing edges, continuous through 0.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
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

// Which of the two cubes is a primitive box and which a hull (the lower one first).
struct Pair {
  bool lower_hull, upper_hull;
};

std::string PairName(const ::testing::TestParamInfo<Pair>& info) {
  return std::string(info.param.upper_hull ? "Hull" : "Box") + "On" +
         (info.param.lower_hull ? "Hull" : "Box");
}

CollisionGeometry Cube(bool hull) {
  return hull ? BoxHull(Vector3d::Constant(kSide))
              : Primitive(ShapeType::kBox, 0, 0, Vector3d::Constant(kSide));
}

class PolytopePairsTest : public ::testing::TestWithParam<Pair> {
 protected:
  // The contacts of the upper cube (geometry 1) at `upper` on the lower one (0) at the origin,
  // normals from the lower toward the upper.
  std::vector<ContactPoint> Collide(const Pose& upper) {
    std::vector<ContactPoint> out;
    narrow_.Collide(1, upper, 0, Pose(), &out);
    for (ContactPoint& c : out) {  // the narrow phase may order the pair either way
      if (c.geometry_a == 0) {
        c.normal = -c.normal;
        std::swap(c.geometry_a, c.geometry_b);
      }
    }
    return out;
  }
  double Distance(const Pose& upper) { return narrow_.SignedDistance(1, upper, 0, Pose(), 1.0); }

  const std::vector<CollisionGeometry> geometries_ = {Cube(GetParam().lower_hull),
                                                      Cube(GetParam().upper_hull)};
  NarrowPhase narrow_{geometries_};
};

TEST_P(PolytopePairsTest, ATurnedCubeStandsOnTheWholeOverlapOfTheTwoFaces) {
  // Turned 0.3 rad and 1 cm off: neither square holds a corner of the other, so the overlap is
  // an octagon, each corner an edge of one crossing an edge of the other.
  const Pose X = Upper(0.3, 0.0, 1e-4);
  const std::vector<ContactPoint> points = Collide(X);
  ASSERT_EQ(points.size(), 8u);
  for (const ContactPoint& c : points) {
    EXPECT_NEAR(c.depth, 1e-4, 1e-12);
    EXPECT_LT((c.normal - Vector3d::UnitZ()).norm(), 1e-12);
    // On the boundary of the lower face or of the upper one (in its own frame), half-way
    // between the two faces.
    const Vector3d p = c.point;
    const Vector3d u = X.R.transpose() * (p - X.p);
    const double lower_edge = std::max(std::abs(p.x()), std::abs(p.y()));
    const double upper_edge = std::max(std::abs(u.x()), std::abs(u.y()));
    EXPECT_LE(lower_edge, 0.5 * kSide + 1e-12);
    EXPECT_LE(upper_edge, 0.5 * kSide + 1e-12);
    EXPECT_TRUE(std::abs(lower_edge - 0.5 * kSide) < 1e-9 ||
                std::abs(upper_edge - 0.5 * kSide) < 1e-9)
        << p.transpose();
    EXPECT_NEAR(p.z(), 0.5 * kSide - 0.5e-4, 1e-12);
  }
  // Flat and evenly sunk: the spring force is depth times the overlap's corners (8), up.
  EXPECT_NEAR(SpringWrench(points).force.z(), 8e-4, 1e-12);
}

TEST_P(PolytopePairsTest, TheContactWrenchIsContinuousAsTheUpperCubeTilts) {
  // Tilted through -2..2 mrad in 1e-5 rad steps. Each point's depth changes by at most its
  // distance from the upper centre (< 0.09 m) times the step, and a point enters or leaves at
  // depth 0: the force sum over at most 8 points changes by at most 8 * 0.09 * step per step.
  // Each point's moment, depth (< 4e-4 m) times its lever in the faces (< 0.08 m), changes by
  // at most 0.09 step * 0.08 + 4e-4 * 0.1 step (the point moves) < 0.01 step. A point of depth
  // ~2e-4 m dropped or taken in (culling, or one EPA point jumping) is ten times these bounds.
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

TEST_P(PolytopePairsTest, TheSignedDistanceIsTheGapOrMinusTheDepth) {
  // Face over face, turned: the gap along z; sunk: minus the depth (the root function's sign
  // changes where the faces meet, not before).
  for (const double h : {2e-3, 1e-6, 0.0, -1e-6, -3e-4}) {
    EXPECT_NEAR(Distance(Upper(0.3, 0.0, -h)), h, 1e-12) << "gap " << h;
    if (h != 0.0) {
      EXPECT_EQ(Collide(Upper(0.3, 0.0, -h)).empty(), h > 0.0) << "gap " << h;
    }
  }
}

TEST_P(PolytopePairsTest, CrossingEdgesAreApartByTheirDistance) {
  // The lower cube rolled 45 degrees about y: its highest edge runs along y. The upper one
  // rolled 45 degrees about x: its lowest edge runs along x. The two edges cross at right
  // angles above the origin, and no face separates the cubes as well as their edges' axis (z).
  const double half_diagonal = 0.5 * std::sqrt(2.0) * kSide;
  Pose lower, upper;
  lower.R = AxisAngleRotation(Vector3d::UnitY(), M_PI / 4);
  upper.R = AxisAngleRotation(Vector3d::UnitX(), M_PI / 4);
  std::vector<ContactPoint> out;
  for (const double gap : {1e-2, 1e-4, 1e-7}) {
    upper.p = Vector3d(0.0, 0.0, 2 * half_diagonal + gap);
    EXPECT_NEAR(narrow_.SignedDistance(1, upper, 0, lower, 1.0), gap, 1e-12) << gap;
    out.clear();
    narrow_.Collide(1, upper, 0, lower, &out);
    EXPECT_TRUE(out.empty()) << gap;
  }
  // 0.1 mm into each other: points at the edges' crossing, normal along z, that deep.
  upper.p = Vector3d(0.0, 0.0, 2 * half_diagonal - 1e-4);
  EXPECT_NEAR(narrow_.SignedDistance(1, upper, 0, lower, 1.0), -1e-4, 1e-12);
  out.clear();
  narrow_.Collide(1, upper, 0, lower, &out);
  ASSERT_FALSE(out.empty());
  double deepest = 0.0;
  for (const ContactPoint& c : out) {
    deepest = std::max(deepest, c.depth);
    EXPECT_LT(std::abs(std::abs(c.normal.z()) - 1.0), 1e-6) << c.normal.transpose();
    EXPECT_LT(c.point.head<2>().norm(), 1e-3) << c.point.transpose();
  }
  EXPECT_NEAR(deepest, 1e-4, 1e-8);
}

INSTANTIATE_TEST_SUITE_P(Cubes, PolytopePairsTest,
                         ::testing::Values(Pair{false, false}, Pair{false, true}, Pair{true, false},
                                           Pair{true, true}),
                         PairName);

}  // namespace
}  // namespace mbstream

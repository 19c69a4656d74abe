// Primitive meshes, polyprism outlines with arcs, and scenes built from scripts.
#include <gtest/gtest.h>

#include <map>
#include <numbers>
#include <random>

#include "tests/viewer/script_test_util.h"
#include "viewer/model/script_scene.h"
#include "viewer/model/shape_mesh.h"
#include "viewer/script/polyprism_outline.h"

namespace mbstream::viewer {
namespace {

namespace ss = scene_script;
using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kPi = std::numbers::pi;

// Every undirected edge is shared by exactly two faces; with `oriented`, in opposite
// directions (consistent orientation).
bool IsClosed(const Mesh& mesh, bool oriented) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& face : mesh.faces) {
    for (size_t i = 0; i < face.size(); ++i) ++directed[{face[i], face[(i + 1) % face.size()]}];
  }
  for (const auto& [edge, count] : directed) {
    const auto reverse = directed.find({edge.second, edge.first});
    const int back = reverse == directed.end() ? 0 : reverse->second;
    if (oriented ? (count != 1 || back != 1) : (count + back != 2)) return false;
  }
  return true;
}

// Volume by the divergence theorem (fan triangulation of each planar face).
double Volume(const Mesh& mesh) {
  double six_v = 0;
  for (const auto& face : mesh.faces) {
    for (size_t i = 1; i + 1 < face.size(); ++i) {
      six_v += mesh.points[face[0]].dot(mesh.points[face[i]].cross(mesh.points[face[i + 1]]));
    }
  }
  return six_v / 6;
}

TEST(ShapeMesh, PrimitivesAreClosedOutwardAndOfTheRightSize) {
  const Mesh cylinder = CylinderMesh({80, 12, 300});
  EXPECT_EQ(cylinder.points.size(), 24u);
  EXPECT_EQ(cylinder.faces.size(), 14u);
  EXPECT_TRUE(IsClosed(cylinder, true));
  const double hexagon_area = 0.5 * 12 * 40 * 40 * std::sin(2 * kPi / 12);
  EXPECT_NEAR(Volume(cylinder), hexagon_area * 300, 1e-6);
  for (const Vector3d& p : cylinder.points) {
    EXPECT_NEAR(p.head<2>().norm(), 40, 1e-12);
    EXPECT_TRUE(p.z() == 0 || p.z() == 300);
  }

  const Mesh cube = CubeMesh({Vector3d(10, 20, 30)});
  EXPECT_TRUE(IsClosed(cube, true));
  EXPECT_NEAR(Volume(cube), 6000, 1e-9);

  ss::ConeShape cone_shape;
  cone_shape.center = Vector3d(1, 2, 3);
  cone_shape.direction = Vector3d(1, 0, 0);
  cone_shape.diameter = 20;
  cone_shape.resolution = 64;
  cone_shape.length = 30;
  const Mesh cone = ConeMesh(cone_shape);
  EXPECT_TRUE(IsClosed(cone, true));
  EXPECT_GT(Volume(cone), 0.98 * kPi * 100 * 30 / 3);
  EXPECT_TRUE(cone.points.back().isApprox(Vector3d(31, 2, 3)));

  const Mesh sphere = SphereMesh({25, 32});
  EXPECT_TRUE(IsClosed(sphere, true));
  for (const Vector3d& p : sphere.points) EXPECT_NEAR(p.norm(), 25, 1e-9);
  EXPECT_NEAR(Volume(sphere), 4.0 / 3 * kPi * 25 * 25 * 25, 0.03 * 4.0 / 3 * kPi * 25 * 25 * 25);
}

TEST(ShapeMesh, TheSeedWedgeIsAClosedSolid) {
  const ss::Translation translation = ss::TranslateScript(R"(Module Wedge Points
    0 0.0 0.0 0.0  1 50.0 15.0 0.0  2 50.0 75.0 0.0  3 0.0 75.0 0.0
    4 50.0 15.0 15.0  5 50.0 75.0 15.0  6 0.0 75.0 20.0  7 0.0 0.0 20.0
    Polygons (0 1 2 3) (1 2 5 4)(2 3 6 5) (3 6 7 0) (7, 4, 1, 0)(4 5 6 7);)");
  ASSERT_TRUE(translation.ok());
  const Mesh wedge = ModuleMesh(std::get<ss::ModuleShape>(translation.script.parts[0].shape));
  EXPECT_EQ(wedge.points.size(), 8u);
  EXPECT_EQ(wedge.faces.size(), 6u);
  EXPECT_TRUE(IsClosed(wedge, false));  // as written, faces are not all oriented alike
}

ss::PolyprismShape Prism(const std::string& outline) {
  const ss::Translation translation = ss::TranslateScript("Polyprism P Height 10 " + outline + ";");
  EXPECT_TRUE(translation.ok()) << ss::testing::ErrorsOf(translation).front();
  return std::get<ss::PolyprismShape>(translation.script.parts.at(0).shape);
}

std::vector<Vector2d> Outline(const std::string& outline) {
  ss::Diagnostics diagnostics;
  return ss::PolyprismOutline(Prism(outline), &diagnostics);
}

TEST(PolyprismOutline, ArcsRunClockwiseForPositiveRadiusAndLargeTakesTheLongWay) {
  // From (-1, 0) to (1, 0) with radius sqrt(2): centre (0, -1) or (0, 1).
  const double r = std::sqrt(2.0);
  struct Expect {
    std::string arc;
    Vector2d centre;
    double top;  // the arc's highest (or lowest) y
  };
  const std::vector<Expect> cases = {
      {"Arc to 1 0 radius " + ss::FormatNumber(r) + " res 8",
       {0, -1},
       r - 1},  // cw short: bulges up
      {"Arc to 1 0 radius -" + ss::FormatNumber(r) + " res 8", {0, 1}, 1 - r},  // ccw short: down
      {"Arc large to 1 0 radius " + ss::FormatNumber(r) + " res 8", {0, 1}, 1 + r},  // cw long: up
      {"Arc Large to 1 0 radius -" + ss::FormatNumber(r) + " res 8", {0, -1}, -1 - r},  // ccw long
  };
  for (const Expect& c : cases) {
    const std::vector<Vector2d> points = Outline("0 -5 -1 0 " + c.arc);
    ASSERT_EQ(points.size(), 10u) << c.arc;  // (0,-5), (-1,0), 7 inner points, (1,0)
    double extreme = 0;
    for (size_t i = 1; i < points.size(); ++i) {
      EXPECT_NEAR((points[i] - c.centre).norm(), r, 1e-9) << c.arc;
      if (std::abs(points[i].y()) > std::abs(extreme)) extreme = points[i].y();
    }
    EXPECT_NEAR(extreme, c.top, 0.05) << c.arc;
  }
}

TEST(PolyprismOutline, SemicircleWhenTheRadiusIsHalfTheChordAndPrismVolume) {
  const std::vector<Vector2d> points = Outline("0 0 10 0 10 10 Arc to 0 10 radius -5 res 64");
  for (size_t i = 3; i < points.size(); ++i) {
    EXPECT_NEAR((points[i] - Vector2d(5, 10)).norm(), 5, 1e-9);
    EXPECT_GE(points[i].y(), 10 - 1e-9);  // anticlockwise from (10,10) to (0,10): bulges up
  }
  const Mesh mesh = PolyprismMesh(Prism("0 0 10 0 10 10 Arc to 0 10 radius -5 res 64"));
  EXPECT_TRUE(IsClosed(mesh, true));
  EXPECT_NEAR(Volume(mesh), (100 + kPi * 25 / 2) * 10, 1.0);
  // A clockwise outline is turned round: the volume stays positive.
  EXPECT_NEAR(Volume(PolyprismMesh(Prism("0 0 0 10 10 10 10 0"))), 1000, 1e-9);
}

TEST(ScriptScene, VisualsFollowTheirLinksWithTheNearestColour) {
  const ss::Translation translation = ss::TranslateScript(
      ss::testing::ReadFile(ss::testing::SourcePath("models/irb1600/irb1600.scene")));
  ASSERT_TRUE(translation.ok()) << ss::testing::ErrorsOf(translation).front();
  const SceneDescription scene = SceneFromScript(translation.script);
  EXPECT_EQ(scene.title, "IRB1600");
  EXPECT_EQ(scene.frame_names.size(), 7u);
  ASSERT_EQ(scene.probes.size(), 1u);
  EXPECT_EQ(scene.probes[0].name, "Tcp");
  EXPECT_DOUBLE_EQ(*scene.scene_box_m, 1.2);
  std::map<int, int> per_frame;
  for (const VisualPart& visual : scene.visuals) {
    ++per_frame[visual.frame];
    EXPECT_TRUE(std::holds_alternative<Mesh>(visual.geometry));
    if (visual.name == "MotorCap") {
      EXPECT_EQ(visual.color, Vector3d(0.25, 0.25, 0.28));
    }
    if (visual.name == "Axis4Motor") {
      EXPECT_EQ(visual.color, Vector3d(0.62, 0.62, 0.64));
    }
  }
  for (int k = 0; k <= 6; ++k) EXPECT_GE(per_frame[k], 1) << "link " << k;
  EXPECT_EQ(per_frame.count(kWorldFrame), 0u);
}

TEST(ScriptScene, RenderedStandaloneComponentsStandInWorld) {
  const ss::Translation translation = ss::TranslateScript(std::string(ss::testing::kSeedDevice) +
                                                          R"(Cube Floor 2000 2000 10;
    Cube Leg 10 10 10; Set Table add Leg (x 5) Leg (x 50);
    Render Floor color 0.2 0.2 0.2; Render Table color 1 0 0; Render Leg color 0 1 0;)");
  ASSERT_TRUE(translation.ok());
  const SceneDescription scene = SceneFromScript(translation.script);
  ASSERT_EQ(scene.visuals.size(), 3u);  // Floor, Leg twice through Table; Leg alone: a component
  for (const VisualPart& visual : scene.visuals) EXPECT_EQ(visual.frame, kWorldFrame);
  EXPECT_EQ(scene.visuals[1].color, Vector3d(0, 1, 0));  // the part's own Render wins
  EXPECT_NEAR(scene.visuals[2].placement.translation().x(), 0.05, 1e-15);
}

}  // namespace
}  // namespace mbstream::viewer

// Runs with collision meshes (issue 44; docs/contact.md, "Meshes"): a box given as an STL mesh
// rests on a plane exactly as the primitive box does; the cube mesh dropped turned comes to
// rest on a face; a non-convex L-shaped mesh rests on its hull on a plane, and a ball dropped
// over its notch rests on the hull (sphere against a convex polytope, in closed form). The
// scenes are SDFormat worlds in tests/data/contact/, their meshes beside them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "server/contact/contact_forces.h"
#include "server/contact/contact_law.h"
#include "server/engine/engine.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/parse/model_file.h"
#include "server/parse/sdf_import.h"
#include "server/sim/run_validation.h"
#include "tests/server/contact/contact_scene.h"

namespace mbstream {
namespace {

using namespace contact_testing;

constexpr double kG = 9.81;

// The suites' run with the meshes' dissipation.
RunConfig MeshConfig(double duration, double interval) {
  RunConfig config = Config(duration, interval);
  config.contact.dissipation = 20.0;
  return config;
}

double FastestAfter(const RunResult& r, double t0) {
  double fastest = 0.0;
  for (size_t f = 0; f < r.t.size(); ++f) {
    if (r.t[f] < t0) continue;
    for (int j = 0; j < r.num_dofs; ++j)
      fastest = std::max(fastest, std::abs(r.qd[f * r.num_dofs + j]));
  }
  return fastest;
}

const double kPairStiffness = contact_law::CombineStiffness(1e5, 1e5);

// The mesh box's hull is its eight corners, the primitive box's contacts its corners too: the
// two runs see the same contact points (summed in another order: rounding, 1e-16 relative),
// so their trajectories agree to what the error control lets such a difference grow to.
TEST(MeshContactTest, AnStlBoxRestsAsThePrimitiveBoxDoes) {
  const Model mesh = Scene("box_mesh_on_plane.sdf");
  const Model box = Scene("box_on_plane.sdf");
  ASSERT_EQ(mesh.collisions.size(), 2u);
  ASSERT_EQ(mesh.collisions[1].shape.type, ShapeType::kConvex);
  const RunConfig config = MeshConfig(3.0, 0.01);
  const RunResult a = RunScene(mesh, config);
  const RunResult b = RunScene(box, config);
  ASSERT_EQ(a.t.size(), b.t.size());
  double worst = 0.0;
  for (size_t k = 0; k < a.q.size(); ++k) worst = std::max(worst, std::abs(a.q[k] - b.q[k]));
  const size_t last = a.t.size() - 1;
  const double depth = 0.1 - Q(a, last, 2);
  const double expected = 2.0 * kG / kPairStiffness;  // the contact force m g = k depth
  printf("RESULT mesh box vs primitive box: largest position difference %.3g m\n", worst);
  printf("RESULT mesh box penetration %.12g expected %.12g rel %.3g\n", depth, expected,
         depth / expected - 1);
  EXPECT_LT(worst, 1e-9);
  EXPECT_NEAR(depth / expected, 1.0, 1e-6);
  EXPECT_LE(FastestAfter(a, 1.0), config.contact.stiction_tolerance);
}

// The cube mesh standing on a table that is a primitive box, then a mesh: each bottom corner of
// the hull inside the table is a point (narrow_phase.h), so it stands as on the plane: sunk
// m g / k, still.
TEST(MeshContactTest, ACubeMeshStandsOnABoxAndOnAHullAsOnThePlane) {
  for (const char* scene : {"mesh_box_on_table.sdf", "mesh_box_on_mesh_table.sdf"}) {
    const Model model = Scene(scene);
    ASSERT_EQ(model.collisions.size(), 2u);
    const RunConfig config = MeshConfig(3.0, 0.01);
    const RunResult r = RunScene(model, config);
    const size_t last = r.t.size() - 1;
    const double depth = 0.1 - Q(r, last, 2);
    const double expected = 2.0 * kG / kPairStiffness;
    printf("RESULT %s: penetration %.12g expected %.12g rel %.3g; fastest after 1 s %.3g\n", scene,
           depth, expected, depth / expected - 1, FastestAfter(r, 1.0));
    EXPECT_NEAR(depth / expected, 1.0, 1e-6) << scene;
    EXPECT_LE(FastestAfter(r, 1.0), config.contact.stiction_tolerance) << scene;
    EXPECT_NEAR(Q(r, last, 0), 0.1, 1e-6) << scene;  // where it was put
  }
}

// Dropped from 0.4 m turned by (0.5, 0.3, 0.2): it lands on a corner, tumbles and comes to
// rest on one of its faces, its centre m g / k below 0.1 m, one body axis vertical.
TEST(MeshContactTest, ACubeMeshDroppedTurnedComesToRestOnAFace) {
  const Model model = Scene("tumbling_cube_mesh.sdf");
  RunConfig config = MeshConfig(4.0, 0.01);
  config.rtol = 1e-8;
  config.atol = 1e-10;
  config.contact.mu_static = config.contact.mu_dynamic = 0.5;
  const RunResult r = RunScene(model, config);
  const size_t last = r.t.size() - 1;
  const double depth = 0.1 - Q(r, last, 2);
  const Eigen::Quaterniond q(Q(r, last, 3), Q(r, last, 4), Q(r, last, 5), Q(r, last, 6));
  const Matrix3d R = q.normalized().toRotationMatrix();
  double vertical = 0.0;  // the body axis closest to the world's z
  for (int k = 0; k < 3; ++k) vertical = std::max(vertical, std::abs(R(2, k)));
  printf(
      "RESULT tumbling cube: rest depth %.9g expected %.9g; most vertical axis %.12f; "
      "steps %ld\n",
      depth, 2.0 * kG / kPairStiffness, vertical, r.stats.solver.steps);
  EXPECT_NEAR(depth / (2.0 * kG / kPairStiffness), 1.0, 1e-4);
  EXPECT_NEAR(vertical, 1.0, 1e-8);
  EXPECT_LT(std::hypot(Q(r, last, 0), Q(r, last, 1)), 0.5);  // it did not fly away
  EXPECT_LE(FastestAfter(r, 3.5), 1e-3);
}

// Equal 0.2 m cubes turned 0.3 rad and 2 cm off-centre on each other (turned_cubes.sdf): a
// hull on a hull, a box on a hull and a hull on a box, beside two primitive boxes. No corner
// of either is inside the other, so the contacts are the octagon of the two faces' overlap
// (server/contact/polytope_clip.h), which FCL's boxBox2 (ODE's dBoxBox) computes for the two
// boxes independently: each pair with a hull follows the boxes' pair. Before, a pair with a
// hull got one GJK/EPA point that jumped as the cube tilted, and BDF stalled: its 50,000 steps
// without passing t = 0.03 s; now 4,089 steps for the four pairs' 2 s. The centre of mass is
// off the octagon's centre, so each cube settles slightly tilted and sunk a little more than
// m g / k (1.1 %).
TEST(MeshContactTest, TurnedCubesStandOnEqualCubesWhicheverIsAHull) {
  const Model model = Scene("turned_cubes.sdf");
  RunConfig config = MeshConfig(2.0, 0.01);
  config.max_steps = 20000;
  const RunResult r = RunScene(model, config);
  const size_t last = r.t.size() - 1;
  ASSERT_EQ(r.num_positions, 28);  // four free cubes: boxes, then the pairs with a hull
  printf("RESULT turned cubes: %ld steps for 2 s; peak contacts %d\n", r.stats.solver.steps,
         r.stats.contact.contacts_peak);
  EXPECT_EQ(r.stats.contact.contacts_peak, 32);  // eight per pair
  const double rest = 2.0 * kG / kPairStiffness;
  for (int body = 1; body < 4; ++body) {
    double worst = 0.0;  // m or 1 (quaternion), against the boxes' pair over every frame
    for (size_t f = 0; f < r.t.size(); ++f) {
      for (int k = 0; k < 7; ++k) {
        const double offset = k == 0 ? 0.6 * body : 0.0;  // the pairs stand 0.6 m apart
        worst = std::max(worst, std::abs(Q(r, f, 7 * body + k) - Q(r, f, k) - offset));
      }
    }
    const double depth = 0.3 - Q(r, last, 7 * body + 2);
    printf(
        "RESULT turned cube %d: largest difference from the boxes' %.3g; sunk %.9g (m g / k "
        "%.9g)\n",
        body, worst, depth, rest);
    // 6e-8 (a hull on a hull, a hull on a box); 6.6e-6 for the box on the hull, whose
    // reference face is the other one of the two (the points lie on the other face while the
    // cube tilts), which creeps apart at rest below the stiction tolerance.
    EXPECT_LT(worst, 2e-5) << body;
    EXPECT_NEAR(depth / rest, 1.0, 0.02) << body;  // tilted: a little deeper
  }
  EXPECT_LE(FastestAfter(r, 1.0), config.contact.stiction_tolerance);
}

// The L lies on its hull's slanted face x + z = 0.05 (the face bridging its notch, not a face
// of the mesh), which the centre of mass stands over the middle of: its origin comes to rest
// 0.05 / sqrt(2) above the plane less m g / k.
TEST(MeshContactTest, ANonConvexMeshRestsOnItsHull) {
  const Model model = Scene("l_shape_on_plane.sdf");
  const RunResult r = RunScene(model, MeshConfig(3.0, 0.01));
  const size_t last = r.t.size() - 1;
  const double expected = 0.05 / std::sqrt(2.0) - kG / kPairStiffness;
  printf("RESULT L on its hull: height %.12g expected %.12g\n", Q(r, last, 2), expected);
  EXPECT_NEAR(Q(r, last, 2), expected, 2e-9);  // Assimp's float vertices: 0.05 to 1e-9
  EXPECT_LE(FastestAfter(r, 2.0), 1e-3);
}

// A ball over the notch of a fixed L: the L's hull (its top face level, 0.05 / sqrt(2) above
// its origin) holds it; the notch itself would let it sink 0.1 m further. Sphere against a
// convex polytope is in closed form (narrow_phase.h): its depth is exact.
TEST(MeshContactTest, ABallRestsOnTheHullOverTheNotch) {
  const Model model = Scene("ball_on_l_shape.sdf");
  ASSERT_EQ(model.collisions.size(), 2u);
  RunConfig config = MeshConfig(2.0, 0.01);
  config.rtol = 1e-8;
  config.atol = 1e-10;
  const RunResult r = RunScene(model, config);
  const size_t last = r.t.size() - 1;
  const double expected = 0.05 / std::sqrt(2.0) + 0.05 - kG / kPairStiffness;
  printf("RESULT ball on the L's hull: height %.12g expected %.12g (difference %.3g m)\n",
         Q(r, last, 2), expected, Q(r, last, 2) - expected);
  EXPECT_NEAR(Q(r, last, 2), expected, 1e-9);
  // Straight down: the float vertices tilt the face by ~1e-9 rad, friction holds it (v_s).
  EXPECT_LT(std::hypot(Q(r, last, 0), Q(r, last, 1)), 1e-7);
  printf("RESULT ball on the L's hull: fastest after 1.5 s %.3g\n", FastestAfter(r, 1.5));
  EXPECT_LE(FastestAfter(r, 1.5), 1e-6);
}

// A published humanoid's collision meshes (Atlas, from Debian's dart-doc, as
// published_floating_test reads it): each an STL read and hulled. At the default pose 8 pairs
// of its hulls that the adjacency rule lets touch overlap (non-adjacent links whose hulls
// reach into each other: pelvis and the upper legs, up to 7.8 cm); ContactForces leaves
// them out (contact_forces.h), so the robot is not pushed apart, and no other pair touches.
TEST(MeshContactTest, APublishedHumanoidsMeshesBecomeHullsThatDoNotPushItApart) {
  const char* atlas = "/usr/share/doc/dart/data/sdf/atlas/atlas_v3_no_head.urdf";
  const ModelFileImport imported = ImportModelFile(atlas, UrdfImportOptions{.floating_base = true});
  const Model& model = imported.model;
  int hulls = 0;
  size_t vertices = 0;
  for (const CollisionGeometry& g : model.collisions) {
    if (g.shape.type != ShapeType::kConvex) continue;
    ++hulls;
    vertices = std::max(vertices, g.shape.convex.vertices->size());
  }
  Data data(model);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.nq());
  NeutralPositions(model, q.data());
  ForwardKinematics(model, data, q);
  ContactForces contact(model, ContactSettings{});
  Eigen::VectorXd qd = Eigen::VectorXd::Zero(model.nv()), tau = Eigen::VectorXd::Zero(model.nv());
  ASSERT_TRUE(contact.AddForces(data, qd, &tau));
  printf(
      "RESULT Atlas: %zu collisions, %d hulls (largest %d vertices), %d pairs may touch, %d "
      "left out as overlapping at the default pose, %zu contacts there\n",
      model.collisions.size(), hulls, static_cast<int>(vertices), contact.num_allowed_pairs(),
      contact.num_overlapping_at_rest(), contact.contacts().size());
  EXPECT_EQ(hulls, 29);
  EXPECT_EQ(contact.num_overlapping_at_rest(), 8);
  EXPECT_TRUE(contact.contacts().empty());
  EXPECT_EQ(tau.norm(), 0.0);
}

}  // namespace
}  // namespace mbstream

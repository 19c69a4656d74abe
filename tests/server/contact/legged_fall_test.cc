// A published humanoid falls onto the floor and comes to rest (issue 44, "Legged robot"):
// Atlas (Debian's dart-doc, its 29 collision meshes as hulls, a free root: the URDF read with
// floating_base), its joints passive with the model's own damping, dropped from 2 cm above a
// ground plane. It must land, fold, and lie still: its energy falls to a rest, no body goes
// through the floor, and the run's energy balance (the contacts' dissipated work included)
// closes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "server/engine/engine.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/model/coordinate_names.h"
#include "server/parse/model_file.h"
#include "server/sim/run_validation.h"
#include "tests/server/contact/contact_scene.h"

namespace mbstream {
namespace {

constexpr char kAtlas[] = "/usr/share/doc/dart/data/sdf/atlas/atlas_v3_no_head.urdf";

// The lowest point of every hull at positions q (m, world z).
double LowestPoint(const Model& model, const Eigen::VectorXd& q) {
  Data data(model);
  ForwardKinematics(model, data, q);
  double lowest = std::numeric_limits<double>::infinity();
  for (const CollisionGeometry& g : model.collisions) {
    if (g.shape.type != ShapeType::kConvex || g.body < 0) continue;
    const Pose X_WG = data.X_world[g.body] * g.X_BG;
    for (const Vector3d& v : *g.shape.convex.vertices) {
      lowest = std::min(lowest, (X_WG.R * v + X_WG.p).z());
    }
  }
  return lowest;
}

TEST(LeggedFallTest, APublishedHumanoidFallsOntoTheFloorAndComesToRest) {
  if (!std::filesystem::exists(kAtlas)) GTEST_SKIP() << kAtlas << " (Debian's dart-doc) is missing";
  Model model = ImportModelFile(kAtlas, UrdfImportOptions{.floating_base = true}).model;
  // The floor: a plane through the world's origin, normal +z.
  CollisionGeometry floor;
  floor.name = "floor";
  floor.link = "world";
  floor.body = kBase;
  floor.shape.type = ShapeType::kPlane;
  model.collisions.push_back(floor);

  const std::vector<std::string> positions = PositionNames(model);
  const int z = static_cast<int>(std::find(positions.begin(), positions.end(), "pelvis.z") -
                                 positions.begin());
  ASSERT_LT(z, model.nq()) << "no coordinate pelvis.z";
  Eigen::VectorXd q0 = Eigen::VectorXd::Zero(model.nq());
  NeutralPositions(model, q0.data());
  q0(z) = 0.02 - LowestPoint(model, q0);  // its lowest point 2 cm above the floor

  RunConfig config = contact_testing::Config(3.0, 0.05);
  config.rtol = 1e-6;
  config.atol = 1e-8;
  config.contact.stiffness = 1e6;
  config.contact.dissipation = 20.0;
  config.q0 = q0;
  config.qd0 = Eigen::VectorXd::Zero(model.nv());
  RunConfig run = config;
  run.want_torques = false;
  run.drives.resize(static_cast<size_t>(model.nv()));
  ValidateRun(model, run);
  const RunResult result = Simulate(model, run);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  const size_t frames = result.t.size();
  std::printf(
      "RESULT Atlas falls: %ld steps, %.2f s CPU for %.1f s; energy error %.3g; deepest %.4g m; "
      "peak contacts %d; pelvis z from %.4f to %.4f m; kinetic energy at the end %.3g J\n",
      result.stats.solver.steps, result.stats.cpu_s, result.t.back(), result.stats.energy_error_max,
      result.contacts.depth_max, result.contacts.count_peak, contact_testing::Q(result, 0, z),
      contact_testing::Q(result, frames - 1, z), result.kinetic.back());
  // It fell: the pelvis is lower; nothing went into the floor by more than a centimetre.
  EXPECT_LT(contact_testing::Q(result, frames - 1, z), q0(z) - 0.05);
  EXPECT_LT(result.contacts.depth_max, 0.01);
  Eigen::VectorXd q_end(model.nq());
  for (int k = 0; k < model.nq(); ++k) q_end(k) = contact_testing::Q(result, frames - 1, k);
  EXPECT_GT(LowestPoint(model, q_end), -0.01);
  // At rest: its kinetic energy over the last half second below a millijoule, every joint
  // rate below 1e-2.
  for (size_t k = frames - 11; k < frames; ++k) EXPECT_LT(result.kinetic[k], 1e-3) << result.t[k];
  for (int i = 0; i < model.nv(); ++i) {
    EXPECT_LT(std::abs(contact_testing::Qd(result, frames - 1, i)), 1e-2) << "velocity " << i;
  }
  EXPECT_GT(result.contacts.count_peak, 3);
  EXPECT_EQ(result.stats.trust, Trust::kOk) << result.stats.trust_reason;
}

}  // namespace
}  // namespace mbstream

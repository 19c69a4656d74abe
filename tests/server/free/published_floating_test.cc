// A published humanoid on a free root: Boston Dynamics' Atlas (v3, no head, as Debian's
// dart-doc ships it: 27 revolute joints, 6 + 27 velocities) imported with --floating-base
// (UrdfImportOptions::floating_base). In zero gravity with every joint servoed along a sine
// (internal forces only), its total linear and angular momentum stay what they were.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <random>
#include <vector>

#include "server/parse/model_file.h"
#include "tests/server/free/free_run.h"
#include "tests/server/free/free_tree_model.h"

namespace mbstream {
namespace {

constexpr char kAtlas[] = "/usr/share/doc/dart/data/sdf/atlas/atlas_v3_no_head.urdf";

TEST(PublishedFloatingTest, AtlasDrivenInZeroGravityConservesItsMomentum) {
  if (!std::filesystem::exists(kAtlas)) {
    if (std::getenv("MBSTREAM_CI"))
      FAIL() << kAtlas << " is missing: scripts/setup.sh installs dart-doc";
    GTEST_SKIP() << kAtlas << " is missing (Debian's dart-doc)";
  }
  Model model = ImportModelFile(kAtlas, UrdfImportOptions{.floating_base = true}).model;
  ASSERT_EQ(model.free_bodies.size(), 1u);
  EXPECT_EQ(model.bodies[model.free_bodies[0]].name, "pelvis");
  ASSERT_EQ(model.nv(), 6 + 27);
  model.gravity.setZero();
  std::vector<DriveConfig> drives(model.nv());
  int k = 0;
  for (const Body& body : model.bodies) {
    if (body.free()) continue;
    EXPECT_EQ(body.joint.armature, 0.0) << body.joint.name;  // a rotor would carry momentum
    drives[body.v_index] = testing::SineServo(200.0, 5.0, 0.0, 0.3, 2.0 + 0.25 * k++);
  }
  testing::FreeRun run(model, drives);
  std::mt19937 rng(3);
  Eigen::VectorXd y0 = Eigen::VectorXd::Zero(model.nq() + model.nv());
  y0(model.bodies[model.free_bodies[0]].q_index + 3) = 1.0;  // upright, at the origin
  y0.tail(model.nv()) = testing::RandomVelocities(model, rng, 0.5);
  run.Start(y0, Method::kErk, 1e-10);
  Data data(model);
  const Vector6d h0 =
      testing::SpatialMomentum(model, data, y0.head(model.nq()), y0.tail(model.nv()));
  double worst_angular = 0.0, worst_linear = 0.0;
  for (int step = 1; step <= 100; ++step) {
    run.AdvanceTo(0.01 * step);
    const Vector6d h = testing::SpatialMomentum(model, data, run.ode.q(), run.ode.qd());
    worst_angular = std::max(worst_angular, (h.head<3>() - h0.head<3>()).norm() / h0.norm());
    worst_linear = std::max(worst_linear, (h.tail<3>() - h0.tail<3>()).norm() / h0.norm());
  }
  std::printf(
      "Atlas, driven in zero gravity for 1 s: momentum change angular %.2e, linear %.2e "
      "(relative)\n",
      worst_angular, worst_linear);
  EXPECT_LT(worst_angular, 1e-9);
  EXPECT_LT(worst_linear, 1e-9);
}

}  // namespace
}  // namespace mbstream

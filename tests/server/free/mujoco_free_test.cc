// Forward dynamics of a floating-base tree against MuJoCo's (libmujoco 2.2.2, a free joint at
// the root): the same model written as MJCF, random states and forces, qacc compared. Built only
// where CMake finds MuJoCo (tests/server/free/CMakeLists.txt).
#include <gtest/gtest.h>

#include <mujoco/mujoco.h>

#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include "server/dynamics/aba.h"
#include "tests/server/free/free_tree_model.h"
#include "tests/server/free/mjcf.h"

namespace mbstream {
namespace {

TEST(MujocoFreeTest, FloatingTreeForwardDynamicsMatchesMujoco) {
  std::mt19937 rng(11);
  // FloatingTree without rotor inertia, less its fixed-base arm: a free torso with two legs
  // (revolute, prismatic, a fixed link between) and a free box.
  Model full = testing::FloatingTree(rng, /*armature=*/0.0);
  ModelBuilder builder("floating", "world");
  for (const Body& body : full.bodies) {
    if (body.name == "arm1" || body.name == "arm2") continue;
    if (body.free()) {
      builder.AddFreeLink(body.name, body.joint.name, body.X_W0, body.inertia);
    } else {
      builder.AddMovingLink(body.name, full.bodies[body.parent].name, body.joint, body.inertia);
    }
  }
  const Model model = builder.Build();
  ASSERT_EQ(model.nv(), 6 + 4 + 6);

  const std::filesystem::path path =
      std::filesystem::path(::testing::TempDir()) / "mbstream_floating_tree.xml";
  std::ofstream(path) << testing::Mjcf(model);
  char error[1000] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, error, sizeof(error));
  ASSERT_NE(m, nullptr) << error;
  mjData* d = mj_makeData(m);
  ASSERT_EQ(m->nq, model.nq());
  ASSERT_EQ(m->nv, model.nv());

  Data data(model);
  double worst = 0.0;
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::VectorXd q = testing::RandomPositions(model, rng);
    const Eigen::VectorXd qd = testing::RandomVelocities(model, rng, 2.0);
    const Eigen::VectorXd tau = testing::RandomVelocities(model, rng, 5.0);
    for (int k = 0; k < m->nq; ++k) d->qpos[k] = q(k);
    for (int k = 0; k < m->nv; ++k) {
      d->qvel[k] = qd(k);
      d->qfrc_applied[k] = tau(k);
    }
    mj_forward(m, d);
    const Eigen::VectorXd ours = Aba(model, data, q, qd, tau);
    const Eigen::Map<const Eigen::VectorXd> theirs(d->qacc, m->nv);
    worst = std::max(worst, (ours - theirs).norm() / theirs.norm());
  }
  std::printf("floating tree, 100 random states: qacc against MuJoCo %s, worst relative %.2e\n",
              mj_versionString(), worst);
  EXPECT_LT(worst, 1e-9);
  mj_deleteData(d);
  mj_deleteModel(m);
}

}  // namespace
}  // namespace mbstream

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

#include <unistd.h>

#include "server/dynamics/aba.h"
#include "server/parse/model_file.h"
#include "tests/server/free/free_tree_model.h"
#include "tests/server/free/mjcf.h"

namespace mbstream {
namespace {

// Writes `model` as MJCF, loads it in MuJoCo and compares qacc at 100 random states and forces.
void ExpectForwardDynamicsAsMujoco(const Model& model, const char* label, std::mt19937& rng) {
  // One file per test process: ctest runs the tests of this program in parallel.
  const std::filesystem::path path = std::filesystem::path(::testing::TempDir()) /
                                     ("mbstream_mjcf_" + std::to_string(getpid()) + ".xml");
  std::ofstream(path) << testing::Mjcf(model);
  char error[1000] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, error, sizeof(error));
  std::filesystem::remove(path);
  ASSERT_NE(m, nullptr) << error;
  mjData* d = mj_makeData(m);
  ASSERT_EQ(m->nq, model.nq());
  ASSERT_EQ(m->nv, model.nv());

  // MuJoCo numbers its coordinates depth first; the model's order may differ: by joint name.
  std::vector<int> qpos(static_cast<size_t>(model.nq())), dof(static_cast<size_t>(model.nv()));
  for (const Body& body : model.bodies) {
    const int joint = mj_name2id(m, mjOBJ_JOINT, body.joint.name.c_str());
    ASSERT_GE(joint, 0) << body.joint.name;
    const int nq = body.nq(), nv = body.nv();
    for (int k = 0; k < nq; ++k)
      qpos[static_cast<size_t>(body.q_index + k)] = m->jnt_qposadr[joint] + k;
    for (int k = 0; k < nv; ++k)
      dof[static_cast<size_t>(body.v_index + k)] = m->jnt_dofadr[joint] + k;
  }
  Data data(model);
  double worst = 0.0;
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::VectorXd q = testing::RandomPositions(model, rng);
    const Eigen::VectorXd qd = testing::RandomVelocities(model, rng, 2.0);
    const Eigen::VectorXd tau = testing::RandomVelocities(model, rng, 5.0);
    for (int k = 0; k < m->nq; ++k) d->qpos[qpos[static_cast<size_t>(k)]] = q(k);
    for (int k = 0; k < m->nv; ++k) {
      d->qvel[dof[static_cast<size_t>(k)]] = qd(k);
      d->qfrc_applied[dof[static_cast<size_t>(k)]] = tau(k);
    }
    mj_forward(m, d);
    const Eigen::VectorXd ours = Aba(model, data, q, qd, tau);
    Eigen::VectorXd theirs(m->nv);
    for (int k = 0; k < m->nv; ++k) theirs(k) = d->qacc[dof[static_cast<size_t>(k)]];
    worst = std::max(worst, (ours - theirs).norm() / theirs.norm());
  }
  std::printf("%s, 100 random states: qacc against MuJoCo %s, worst relative %.2e\n", label,
              mj_versionString(), worst);
  EXPECT_LT(worst, 1e-9) << label;
  mj_deleteData(d);
  mj_deleteModel(m);
}

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

  ExpectForwardDynamicsAsMujoco(model, "floating tree", rng);
}

// Ball joints (quaternions, MuJoCo's ball joint) in a fixed-base chain with a revolute joint
// between them and below a free torso, through a prismatic joint.
TEST(MujocoFreeTest, BallJointChainsForwardDynamicsMatchMujoco) {
  std::mt19937 rng(13);
  const Model model = testing::BallTree(rng);
  ASSERT_EQ(model.nq(), 4 + 4 + 1 + 4 + 7 + 4 + 1 + 4);
  ASSERT_EQ(model.nv(), 3 + 3 + 1 + 3 + 6 + 3 + 1 + 3);
  ExpectForwardDynamicsAsMujoco(model, "ball-joint chains", rng);
}

// A published humanoid (Atlas v3 of Debian's dart-doc, --floating-base: a free pelvis and 27
// revolute joints about its URDF's axes) against MuJoCo.
TEST(MujocoFreeTest, PublishedAtlasOnAFreeRootMatchesMujoco) {
  constexpr char kAtlas[] = "/usr/share/doc/dart/data/sdf/atlas/atlas_v3_no_head.urdf";
  if (!std::filesystem::exists(kAtlas)) GTEST_SKIP() << kAtlas << " is missing (dart-doc)";
  Model model = ImportModelFile(kAtlas, UrdfImportOptions{.floating_base = true}).model;
  for (Body& body : model.bodies) body.joint.armature = 0.0;  // MJCF written without it
  std::mt19937 rng(12);
  ExpectForwardDynamicsAsMujoco(model, "Atlas on a free root", rng);
}

}  // namespace
}  // namespace mbstream

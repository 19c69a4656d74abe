// Every linkage of models/linkages/ ships a scene script (NAME.scene, written by generate.py)
// and run specs (NAME-driven.json, NAME-passive.json, loaded by
// LoopRunTest.EveryLinkagesRunSpecsLoadAndAreAccepted). The script translates without errors,
// its Device has the model's tree joints in the server's order, and at any joint values its
// link frames are the model's (SceneFromSdf's chain): the script draws what the server runs.
// A ball joint inside the tree is one chain joint of four values JOINT.qw .qx .qy .qz (the
// quaternion of the child in the joint frame), as the server's.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <random>

#include "shared/common/check.h"
#include "tests/viewer/script_test_util.h"
#include "viewer/model/model_scene.h"
#include "viewer/model/script_scene.h"

namespace mbstream::viewer {
namespace {

namespace ss = scene_script;

const char* const kLinkages[] = {"four_bar", "parallelogram", "slider_crank", "delta",
                                 "palletiser"};

std::filesystem::path LinkagePath(const std::string& file) {
  return ss::testing::SourcePath("models/linkages/" + file);
}

SceneDescription ModelScene(const std::string& name) {
  return SceneFromModelText(ss::testing::ReadFile(LinkagePath(name + ".sdf")), name + ".sdf",
                            [](const std::string&) { return std::filesystem::path(); });
}

// The frame after each moving joint, in joint value order.
std::vector<Eigen::Isometry3d> JointFrames(const KinematicChain& chain,
                                           const std::vector<double>& q) {
  std::vector<Eigen::Isometry3d> frames(static_cast<size_t>(chain.frame_count()));
  chain.Compute(q, frames);
  std::vector<Eigen::Isometry3d> out;
  for (size_t j = 0; j < chain.joints().size(); ++j) {
    if (chain.joints()[j].kind != ChainJointKind::kFixed) out.push_back(frames[j + 1]);
  }
  return out;
}

TEST(LinkageScene, EveryLinkageHasAScriptWhoseFramesAreTheModels) {
  std::mt19937 random(31);
  std::uniform_real_distribution<double> value(-0.5, 0.5);
  for (const std::string name : kLinkages) {
    SCOPED_TRACE(name);
    EXPECT_TRUE(std::filesystem::exists(LinkagePath(name + "-driven.json")));
    EXPECT_TRUE(std::filesystem::exists(LinkagePath(name + "-passive.json")));
    const ss::Translation translation =
        ss::TranslateScript(ss::testing::ReadFile(LinkagePath(name + ".scene")));
    ASSERT_TRUE(translation.ok()) << ss::testing::ErrorsOf(translation).front();
    const SceneDescription script = SceneFromScript(translation.script);
    const SceneDescription model = ModelScene(name);
    EXPECT_EQ(script.title, name);
    ASSERT_EQ(script.chain.dof(), model.chain.dof());
    EXPECT_EQ(script.visuals.size(), model.visuals.size());
    for (int trial = 0; trial < 5; ++trial) {
      std::vector<double> q(static_cast<size_t>(model.chain.dof()));
      for (double& v : q) v = trial == 0 ? 0.0 : value(random);
      const std::vector<Eigen::Isometry3d> a = JointFrames(script.chain, q);
      const std::vector<Eigen::Isometry3d> b = JointFrames(model.chain, q);
      ASSERT_EQ(a.size(), b.size());
      for (size_t j = 0; j < a.size(); ++j) {
        EXPECT_LT((a[j].matrix() - b[j].matrix()).cwiseAbs().maxCoeff(), 1e-9)
            << "joint " << j + 1 << " (" << model.chain.dof_joint(static_cast<int>(j)).name
            << "), trial " << trial;
      }
    }
  }
}

TEST(LinkageScene, ABallJointInTheTreeIsOneChainJointTurnedByItsQuaternion) {
  const SceneDescription scene = SceneFromModelText(
      ss::testing::ReadFile(ss::testing::SourcePath("tests/data/delta_ball.sdf")), "delta_ball.sdf",
      [](const std::string&) { return std::filesystem::path(); });
  std::vector<std::string> names;
  for (int i = 0; i < scene.chain.dof(); ++i) names.push_back(scene.chain.dof_joint(i).name);
  const auto first = std::find(names.begin(), names.end(), "wrist");
  ASSERT_NE(first, names.end());
  ASSERT_LT(first + 3, names.end());
  EXPECT_EQ(*(first + 3), "wrist");
  const int v = static_cast<int>(first - names.begin());
  EXPECT_EQ(scene.chain.dof_joint(v).kind, ChainJointKind::kBall);
  EXPECT_EQ(scene.chain.dof(), ModelScene("delta").chain.dof() + 1);  // 4 values for 3 axes
  EXPECT_EQ(scene.initial_q[static_cast<size_t>(v)], 1.0);            // qw: the identity

  // The wrist's child is the joint frame (the frame at the identity quaternion) turned by the
  // quaternion, whatever the other joints do.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> value(-0.5, 0.5);
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<double> q(static_cast<size_t>(scene.chain.dof()));
    for (double& x : q) x = value(random);
    Eigen::Quaterniond quat(value(random), value(random), value(random), value(random));
    for (int k = 0; k < 4; ++k) q[static_cast<size_t>(v + k)] = quat.coeffs()[(k + 3) % 4];
    std::vector<double> identity = q;
    identity[static_cast<size_t>(v)] = 1.0;
    for (int k = 1; k < 4; ++k) identity[static_cast<size_t>(v + k)] = 0.0;
    // The chain joint of value v: its frame index among the moving joints.
    const std::vector<Eigen::Isometry3d> turned = JointFrames(scene.chain, q);
    const std::vector<Eigen::Isometry3d> still = JointFrames(scene.chain, identity);
    int joint = 0;
    for (int i = 0; i < v; ++i)
      joint += scene.chain.dof_joint(i).name != scene.chain.dof_joint(i + 1).name;
    const Eigen::Matrix3d expected =
        still[static_cast<size_t>(joint)].linear() * quat.normalized().toRotationMatrix();
    EXPECT_LT((turned[static_cast<size_t>(joint)].linear() - expected).cwiseAbs().maxCoeff(),
              1e-12);
    EXPECT_LT((turned[static_cast<size_t>(joint)].translation() -
               still[static_cast<size_t>(joint)].translation())
                  .norm(),
              1e-12);
  }

  // Ordered by the server's position names: the four values by their names.
  KinematicChain chain = scene.chain;
  std::vector<std::string> server;
  for (int i = 0; i < chain.dof();) {
    const ChainJoint& joint = chain.dof_joint(i);
    if (joint.kind == ChainJointKind::kBall) {
      for (int k = 0; k < 4; ++k) server.push_back(BallValueName(joint.name, k));
      i += 4;
    } else {
      server.push_back(joint.name);
      ++i;
    }
  }
  std::reverse(server.begin(), server.end());
  EXPECT_THROW(chain.OrderJointValuesBy(server), InputError);  // qz .. qw: out of order
  std::reverse(server.begin(), server.end());
  std::rotate(server.begin(), server.begin() + 1, server.end());
  chain.OrderJointValuesBy(server);
  EXPECT_EQ(chain.dof(), scene.chain.dof());
}

}  // namespace
}  // namespace mbstream::viewer

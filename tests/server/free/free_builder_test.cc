// ModelBuilder::AddFreeLink: the coordinate layout of free bodies (model.h), their default pose,
// children hanging from them, and the refusal of runs until the engine simulates them.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "server/model/model_builder.h"
#include "server/sim/run_config.h"
#include "server/sim/run_validation.h"
#include "shared/common/check.h"
#include "tests/server/free/free_tree_model.h"

namespace mbstream {
namespace {

using testing::Box;

Joint Revolute(const std::string& name, const Vector3d& offset) {
  Joint joint;
  joint.name = name;
  joint.X_PJ.p = offset;
  return joint;
}

// A world: an arm of two revolute joints on the base, a free box, a free torso with a leg
// (revolute) and a fixed foot.
Model World() {
  ModelBuilder builder("world", "world");
  builder.AddMovingLink("a1", "world", Revolute("j1", {0, 0, 0.5}), Box(2.0));
  Pose X_WB;
  X_WB.p = Vector3d(1.0, 2.0, 3.0);
  X_WB.R = AxisAngleRotation(Vector3d::UnitZ(), 0.5);
  builder.AddFreeLink("box", "box", X_WB, Box(1.0));
  builder.AddMovingLink("a2", "a1", Revolute("j2", {0, 0, 0.4}), Box(1.5));
  builder.AddFreeLink("torso", "root", Pose::Identity(), Box(10.0));
  builder.AddMovingLink("leg", "torso", Revolute("hip", {0, 0.1, -0.2}), Box(3.0));
  builder.AddFixedLink("foot", "leg", Pose::Identity(), Box(0.5));
  return builder.Build();
}

TEST(FreeBuilderTest, FreeBodiesHaveSevenPositionsAndSixVelocities) {
  const Model model = World();
  ASSERT_EQ(model.num_bodies(), 5);
  EXPECT_EQ(model.free_bodies, (std::vector<int>{1, 3}));
  EXPECT_TRUE(model.has_free_bodies());
  EXPECT_EQ(model.nq(), 3 + 2 * 7);
  EXPECT_EQ(model.nv(), 3 + 2 * 6);
  EXPECT_EQ(model.num_dofs(), model.nv());
  // a1, box, a2, torso, leg.
  const std::vector<int> q_index{0, 1, 8, 9, 16};
  const std::vector<int> v_index{0, 1, 7, 8, 14};
  for (int i = 0; i < model.num_bodies(); ++i) {
    EXPECT_EQ(model.bodies[i].q_index, q_index[i]) << model.bodies[i].name;
    EXPECT_EQ(model.bodies[i].v_index, v_index[i]) << model.bodies[i].name;
  }
  const Body& box = model.bodies[1];
  EXPECT_TRUE(box.free());
  EXPECT_EQ(box.parent, kBase);
  EXPECT_EQ(box.joint.name, "box");
  EXPECT_STREQ(JointTypeName(box.joint.type), "free");
  EXPECT_EQ(model.bodies[3].joint.name, "root");
  EXPECT_EQ(model.bodies[4].parent, 3);                 // the leg hangs from the free torso
  EXPECT_DOUBLE_EQ(model.bodies[4].inertia.mass, 3.5);  // the fixed foot merged into it
  EXPECT_EQ(model.frames[model.FindFrame("foot")].body, 4);
}

TEST(FreeBuilderTest, NeutralPositionsAreTheDefaultPoses) {
  const Model model = World();
  std::vector<double> q(model.nq(), -1.0);
  NeutralPositions(model, q.data());
  const double half = 0.25;  // half of the box's 0.5 rad about z
  const std::vector<double> expected{
      0.0, 1.0, 2.0, 3.0, std::cos(half), 0.0, 0.0, std::sin(half), 0.0, 0.0, 0.0, 0.0, 1.0,
      0.0, 0.0, 0.0, 0.0};
  ASSERT_EQ(q.size(), expected.size());
  for (size_t k = 0; k < q.size(); ++k) EXPECT_NEAR(q[k], expected[k], 1e-15) << k;
}

TEST(FreeBuilderTest, FixedBaseModelsKeepOneCoordinatePerBody) {
  ModelBuilder builder("arm", "base");
  builder.AddMovingLink("a1", "base", Revolute("j1", {0, 0, 0.5}), Box(2.0));
  builder.AddMovingLink("a2", "a1", Revolute("j2", {0, 0, 0.4}), Box(1.5));
  const Model model = builder.Build();
  EXPECT_FALSE(model.has_free_bodies());
  EXPECT_EQ(model.nq(), 2);
  EXPECT_EQ(model.nv(), 2);
  EXPECT_EQ(model.bodies[1].q_index, 1);
  EXPECT_EQ(model.bodies[1].v_index, 1);
}

TEST(FreeBuilderTest, RefusesABadPoseOrInertiaOrADuplicateName) {
  ModelBuilder builder("world", "world");
  Pose skewed;
  skewed.R(0, 1) = 0.1;
  EXPECT_THROW(builder.AddFreeLink("box", "box", skewed, Box(1.0)), InputError);
  EXPECT_THROW(builder.AddFreeLink("box", "box", Pose::Identity(), Box(0.0)), InputError);
  EXPECT_THROW(builder.AddFreeLink("world", "free", Pose::Identity(), Box(1.0)), InputError);
}

std::string RefusalOf(const Model& model, const RunConfig& config) {
  try {
    ValidateRun(model, config);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(FreeBuilderTest, RunValidationRefusesWhatFreeBodiesCannotDo) {
  const Model model = World();
  RunConfig config;
  config.drives.resize(static_cast<size_t>(model.nv()));
  EXPECT_EQ(RefusalOf(model, config), "");  // the joint formulation, passive, default pose

  RunConfig body = config;
  body.formulation = Formulation::kBodyBaumgarte;
  EXPECT_NE(RefusalOf(model, body)
                .find("free joint 'box' (link 'box') and 1 more: formulation "
                      "body-baumgarte does not simulate free bodies"),
            std::string::npos)
      << RefusalOf(model, body);

  RunConfig driven = config;
  driven.drives[3].kind = DriveConfig::Kind::kTorque;  // box.wx
  EXPECT_NE(RefusalOf(model, driven).find("free joint 'box' (link 'box') has a drive"),
            std::string::npos)
      << RefusalOf(model, driven);

  RunConfig short_q = config;
  short_q.q0 = Eigen::VectorXd::Zero(model.nv());
  EXPECT_NE(RefusalOf(model, short_q).find("initial_q has 15 values and the model has 17"),
            std::string::npos)
      << RefusalOf(model, short_q);

  RunConfig tilted = config;
  tilted.q0 = Eigen::VectorXd::Zero(model.nq());
  NeutralPositions(model, tilted.q0.data());
  tilted.q0(1 + 3) = 1.00001;  // the box's qw: cos(0.25) before
  tilted.q0(9 + 3) = 1.0;      // the torso's
  const std::string refusal = RefusalOf(model, tilted);
  EXPECT_NE(refusal.find("free joint 'box' (link 'box'): initial_q's quaternion"),
            std::string::npos)
      << refusal;
  EXPECT_NE(refusal.find("has norm 1.0"), std::string::npos) << refusal;

  tilted.q0(1 + 3) = std::cos(0.25) + 1e-7;  // within 1e-6 of unit: accepted (normalised)
  EXPECT_EQ(RefusalOf(model, tilted), "");
}

}  // namespace
}  // namespace mbstream

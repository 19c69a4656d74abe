// RunConfig::initial_bodies in the run's initial state: each part given replaces the free
// joint's coordinates, over initial_q (or the model's default pose) and initial_qd (or zero);
// the rest of the state is untouched; ValidateRun refuses a name that is no free body's.
#include <gtest/gtest.h>

#include <cmath>

#include "server/drives/drive_set.h"
#include "server/model/model_builder.h"
#include "server/sim/initial_state.h"
#include "server/sim/run_config.h"
#include "server/sim/run_validation.h"
#include "shared/common/check.h"
#include "tests/server/free/free_tree_model.h"

namespace mbstream {
namespace {

using testing::Box;

// An arm joint, a free box at a turned pose, and a free torso at the origin.
Model World() {
  ModelBuilder builder("world", "world");
  Joint hinge;
  hinge.name = "j1";
  builder.AddMovingLink("a1", "world", hinge, Box(2.0));
  Pose X_WB;
  X_WB.p = Vector3d(1.0, 2.0, 3.0);
  X_WB.R = AxisAngleRotation(Vector3d::UnitZ(), 0.5);
  builder.AddFreeLink("box", "box", X_WB, Box(1.0));
  builder.AddFreeLink("torso", "root", Pose::Identity(), Box(10.0));
  return builder.Build();
}

RunConfig Passive(const Model& model) {
  RunConfig config;
  config.drives.assign(static_cast<size_t>(model.nv()), DriveConfig{});
  return config;
}

Eigen::VectorXd State(const Model& model, const RunConfig& config) {
  return InitialJointState(config, DriveSet(model, config.drives), model);
}

TEST(InitialBodiesTest, PartsGivenReplaceTheDefaultPoseAndTheRestStays) {
  const Model model = World();
  RunConfig config = Passive(model);
  const Eigen::VectorXd before = State(model, config);
  InitialBodyState box{.name = "box"};
  box.position = Eigen::Vector3d(-1.0, 0.5, 7.0);
  box.angular_velocity = Eigen::Vector3d(0.1, 0.2, 0.3);
  config.initial_bodies = {box};
  ASSERT_NO_THROW(ValidateRun(model, config));
  const Eigen::VectorXd y = State(model, config);
  const int nq = model.nq();
  Eigen::VectorXd expected = before;
  expected.segment<3>(1) = *box.position;                   // box.x .y .z
  expected.segment<3>(nq + 1 + 3) = *box.angular_velocity;  // box.wx .wy .wz
  EXPECT_EQ(y, expected);                                   // its quaternion: the model's turn
  EXPECT_NEAR(y[1 + 3], std::cos(0.25), 1e-15);
}

TEST(InitialBodiesTest, PartsGivenApplyOverInitialQAndQd) {
  const Model model = World();
  RunConfig config = Passive(model);
  config.q0 = Eigen::VectorXd::LinSpaced(model.nq(), 0.1, 1.5);
  config.q0.segment<4>(1 + 3) << 1, 0, 0, 0;  // box
  config.q0.segment<4>(8 + 3) << 0, 1, 0, 0;  // torso
  config.qd0 = Eigen::VectorXd::LinSpaced(model.nv(), -1.0, 1.0);
  InitialBodyState torso{.name = "root"};
  torso.quaternion = Eigen::Vector4d(0.0, 0.0, 2.0, 0.0) / 2.0000001;  // normalised
  torso.linear_velocity = Eigen::Vector3d(4.0, 5.0, 6.0);
  config.initial_bodies = {torso};
  const Eigen::VectorXd y = State(model, config);
  const int nq = model.nq();
  Eigen::VectorXd expected(nq + model.nv());
  expected << config.q0, config.qd0;
  expected.segment<4>(8 + 3) << 0, 0, 1, 0;
  expected.segment<3>(nq + 7) = *torso.linear_velocity;
  EXPECT_LT((y - expected).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_EQ(y.head<8>(), config.q0.head<8>());  // the arm and the box as initial_q gives them
}

TEST(InitialBodiesTest, ValidateRunRefusesANameThatIsNoFreeBody) {
  const Model model = World();
  RunConfig config = Passive(model);
  config.initial_bodies = {InitialBodyState{.name = "a1"}};
  try {
    ValidateRun(model, config);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(),
                 "initial_bodies: 'a1' is no free body of the model; give a free joint's name, "
                 "as the model's position names show it (NAME of NAME.x ... NAME.qz)");
  }
  config.initial_bodies = {InitialBodyState{.name = "box"}};
  config.initial_bodies[0].quaternion = Eigen::Vector4d(1.0, 0.1, 0.0, 0.0);
  try {
    ValidateRun(model, config);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("the quaternion has norm 1.00498756"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace mbstream

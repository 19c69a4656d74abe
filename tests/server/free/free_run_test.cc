// A run of a world with free bodies through the engine: the frames' q (nq values) and qd (nv),
// the results files' columns, the wire's frames and model description.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "server/engine/engine.h"
#include "server/model/coordinate_names.h"
#include "server/model/model_builder.h"
#include "server/results/results_csv.h"
#include "server/sim/run_validation.h"
#include "server/wire/frame_conversion.h"
#include "server/wire/model_info.h"
#include "tests/server/free/free_tree_model.h"

namespace mbstream {
namespace {

using testing::Box;

// An arm (one driven revolute joint) and a free box above the floor.
Model ArmAndBox() {
  ModelBuilder builder("world", "world");
  Joint joint;
  joint.name = "j1";
  joint.X_PJ.p = Vector3d(0, 0, 0.5);
  builder.AddMovingLink("a1", "world", joint, Box(2.0));
  Pose X_WB;
  X_WB.p = Vector3d(1.0, 0.0, 2.0);
  builder.AddFreeLink("box", "box", X_WB, Box(1.0));
  return builder.Build();
}

RunConfig Config(const Model& model) {
  RunConfig config;
  config.duration = 0.5;
  config.output_interval = 0.1;
  config.rtol = 1e-10;
  config.atol = 1e-12;
  config.drives.resize(static_cast<size_t>(model.nv()));
  DriveConfig& servo = config.drives[0];
  servo.kind = DriveConfig::Kind::kPdServo;
  servo.kp = 100.0;
  servo.kd = 10.0;
  servo.trajectory.offset = 0.3;
  config.qd0 = Eigen::VectorXd::Zero(model.nv());
  config.qd0(1) = 0.5;  // box.vx
  config.qd0(6) = 2.0;  // box.wz
  return config;
}

TEST(FreeRunTest, FramesCarryPositionsAndVelocitiesOfEveryCoordinate) {
  const Model model = ArmAndBox();
  const RunConfig config = Config(model);
  ValidateRun(model, config);
  const RunResult result = Simulate(model, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  ASSERT_EQ(result.num_frames(), 6);
  EXPECT_EQ(result.num_dofs, 7);
  EXPECT_EQ(result.num_positions, 8);
  EXPECT_EQ(result.q.size(), 6u * 8);
  EXPECT_EQ(result.qd.size(), 6u * 7);
  EXPECT_EQ(result.position_names,
            (std::vector<std::string>{"j1", "box.x", "box.y", "box.z", "box.qw", "box.qx", "box.qy",
                                      "box.qz"}));
  EXPECT_EQ(result.joint_names, (std::vector<std::string>{"j1", "box.vx", "box.vy", "box.vz",
                                                          "box.wx", "box.wy", "box.wz"}));
  // The box falls freely: x = 1 + 0.5 t, z = 2 - g t^2 / 2, turning about z at 2 rad/s.
  const int last = 5;
  const double t = result.t[last];
  const double* q = &result.q[last * 8];
  EXPECT_NEAR(q[1], 1.0 + 0.5 * t, 1e-9);
  EXPECT_NEAR(q[3], 2.0 - 0.5 * 9.81 * t * t, 1e-9);
  EXPECT_NEAR(q[4], std::cos(t), 1e-9);  // qw of a turn by 2 t about z
  EXPECT_NEAR(q[7], std::sin(t), 1e-9);
  EXPECT_NEAR(result.qd[last * 7 + 3], -9.81 * t, 1e-9);  // box.vz
  EXPECT_EQ(result.stats.summary.q_final.size(), 8u);

  // The results files: joints.csv by position, velocities.csv and torques.csv by velocity.
  const std::vector<results_csv::Series> series = results_csv::SeriesOf(result);
  EXPECT_EQ(series[0].file, "joints.csv");
  EXPECT_EQ(series[0].header, "t,j1,box.x,box.y,box.z,box.qw,box.qx,box.qy,box.qz");
  EXPECT_EQ(series[0].width, 8);
  EXPECT_EQ(series[1].header, "t,j1,box.vx,box.vy,box.vz,box.wx,box.wy,box.wz");
  EXPECT_EQ(series[1].width, 7);

  // The wire: Frame.q has nq values, qd nv, and back again.
  v1::Frame frame;
  FrameToProto(result, last, &frame);
  EXPECT_EQ(frame.q_size(), 8);
  EXPECT_EQ(frame.qd_size(), 7);
  v1::RunInfo info;
  info.set_num_dofs(7);
  for (const std::string& name : result.joint_names) info.add_joint_names(name);
  info.set_num_positions(8);
  for (const std::string& name : result.position_names) info.add_position_names(name);
  info.set_has_torques(result.has_torques);
  const RunResult back = ResultFromFrames(info, {frame});
  EXPECT_EQ(back.positions(), 8);
  EXPECT_EQ(back.q, std::vector<double>(q, q + 8));
}

TEST(FreeRunTest, ModelInfoNamesEveryCoordinate) {
  const Model model = ArmAndBox();
  v1::ModelInfo info;
  DescribeModel(model, {}, &info);
  EXPECT_EQ(info.dofs(), 7);
  EXPECT_EQ(info.positions(), 8);
  ASSERT_EQ(info.position_names_size(), 8);
  EXPECT_EQ(info.position_names(4), "box.qw");
  ASSERT_EQ(info.velocity_names_size(), 7);
  EXPECT_EQ(info.velocity_names(6), "box.wz");
  ASSERT_EQ(info.joints_size(), 2);
  EXPECT_EQ(info.joints(1).type(), "free");
  EXPECT_EQ(info.joints(1).lower(), 0.0);
  EXPECT_EQ(JointNames(model), VelocityNames(model));
}

TEST(FreeRunTest, EveryFixedStepAndAdaptiveMethodRunsAFreeBody) {
  const Model model = ArmAndBox();
  for (const Method method :
       {Method::kBdf, Method::kAdams, Method::kErk, Method::kDirk, Method::kRk4, Method::kEuler}) {
    RunConfig config = Config(model);
    config.method = method;
    config.rtol = 1e-8;
    config.atol = 1e-10;
    config.fixed_step = 1e-3;
    ValidateRun(model, config);
    const RunResult result = Simulate(model, config);
    ASSERT_EQ(result.stats.status, RunStatus::kFinished)
        << MethodName(method) << ": " << result.stats.message;
    const double* q = &result.q[5 * 8];
    EXPECT_NEAR(std::hypot(std::hypot(q[4], q[5]), std::hypot(q[6], q[7])), 1.0, 1e-12)
        << MethodName(method);
    const double tolerance = method == Method::kEuler ? 1e-2 : 1e-6;
    EXPECT_NEAR(q[3], 2.0 - 0.5 * 9.81 * 0.25, tolerance) << MethodName(method);
    EXPECT_GE(result.stats.energy_error_max, 0.0);
  }
}

}  // namespace
}  // namespace mbstream

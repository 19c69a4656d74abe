// The palletising arm (models/linkages/palletiser.sdf): two parallelograms in series keep its
// tool flange level. A driven run (every axis prescribed, axis 6 turning back what axis 1
// turns) keeps the tool's orientation constant; a passive one (the turret spun, the arm
// falling) keeps the flange level and the energy.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "server/kinematics/forward_kinematics.h"
#include "server/parse/sdf_import.h"
#include "server/sim/loop_run.h"

namespace mbstream {
namespace {

const std::string kPalletiser =
    std::string(MBSTREAM_SOURCE_DIR) + "/models/linkages/palletiser.sdf";

int JointIndex(const Model& model, const std::string& name) {
  for (int i = 0; i < model.num_dofs(); ++i) {
    if (model.bodies[i].joint.name == name) return i;
  }
  ADD_FAILURE() << "no joint " << name;
  return 0;
}

// The tool's rotation from its drawn orientation (rad), its tilt from the vertical (rad) and
// the tool point's position, at tree coordinates q.
struct ToolPose {
  double rotation = 0.0, tilt = 0.0;
  Vector3d tcp;
};

ToolPose Tool(const Model& model, Data& data, const double* q) {
  ForwardKinematics(model, data, Eigen::Map<const Eigen::VectorXd>(q, model.num_dofs()));
  const Pose& X = data.X_world[model.FindBody("tool")];
  ToolPose pose;
  pose.rotation = Eigen::AngleAxisd(X.R).angle();
  // (atan2, not acos of R(2, 2): that is 1.5e-8 for one ulp below 1)
  pose.tilt = std::atan2(std::hypot(X.R(0, 2), X.R(1, 2)), X.R(2, 2));
  pose.tcp = X.p;
  return pose;
}

// The tool's worst over a run's frames: its largest rotation and tilt from the drawn pose, and
// how far its point moved from it (travel) and dropped below it.
struct ToolWorst {
  double rotation = 0.0, tilt = 0.0, travel = 0.0, drop = 0.0;
};

ToolWorst WorstOf(const Model& model, const RunResult& result) {
  Data data(model);
  const ToolPose drawn = Tool(model, data, Eigen::VectorXd::Zero(model.num_dofs()).eval().data());
  ToolWorst worst;
  for (int k = 0; k < result.num_frames(); ++k) {
    const ToolPose pose = Tool(model, data, &result.q[static_cast<size_t>(k) * result.num_dofs]);
    worst.rotation = std::max(worst.rotation, pose.rotation);
    worst.tilt = std::max(worst.tilt, pose.tilt);
    worst.travel = std::max(worst.travel, (pose.tcp - drawn.tcp).norm());
    worst.drop = std::max(worst.drop, drawn.tcp.z() - pose.tcp.z());
  }
  return worst;
}

void Sine(DriveConfig& drive, double amplitude, double omega, double phase) {
  drive.kind = DriveConfig::Kind::kPrescribed;
  drive.trajectory.amplitude = {amplitude};
  drive.trajectory.omega = {omega};
  drive.trajectory.phase = {phase};
}

RunConfig Config(const Model& model) {
  RunConfig config;
  config.duration = 2.0;
  config.output_interval = 0.01;
  config.drives.assign(model.num_dofs(), DriveConfig{});
  config.rtol = 1e-10;
  config.atol = 1e-12;
  return config;
}

TEST(PalletiserTest, DrivenItsParallelogramsKeepTheToolsOrientation) {
  const SdfImport sdf = ImportSdfFile(kPalletiser);
  ASSERT_EQ(sdf.loops.size(), 2u);
  ASSERT_EQ(sdf.model.num_dofs(), 8);
  RunConfig config = Config(sdf.model);
  // models/linkages/palletiser-driven.json: the turret swings +-0.8 rad, axis 6 turns it back.
  Sine(config.drives[JointIndex(sdf.model, "axis1")], 0.8, M_PI, 0.0);
  Sine(config.drives[JointIndex(sdf.model, "axis2")], 0.3, M_PI, 0.0);
  Sine(config.drives[JointIndex(sdf.model, "axis3")], 0.4, 2.0 * M_PI, M_PI);
  Sine(config.drives[JointIndex(sdf.model, "axis6")], 0.8, M_PI, M_PI);
  config.want_torques = true;
  const RunResult result = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_EQ(result.stats.formulation, "kinematic");
  EXPECT_EQ(result.stats.loops.equations, 10);
  EXPECT_EQ(result.stats.loops.independent, 4);
  EXPECT_EQ(result.stats.loops.mobility, 4);
  const ToolWorst worst = WorstOf(sdf.model, result);
  EXPECT_GT(worst.travel, 0.5);  // the tool moves
  EXPECT_LT(worst.rotation, 1e-10);
  EXPECT_LT(result.stats.drift_position_max, 1e-11);
}

TEST(PalletiserTest, PassiveItKeepsItsEnergyAndItsFlangeLevel) {
  const SdfImport sdf = ImportSdfFile(kPalletiser);
  RunConfig config = Config(sdf.model);
  // models/linkages/palletiser-passive.json: released with the turret at 1 rad/s. The arm
  // falls forward; at t = 0.64 s the lower arm is horizontal, in line with the rear
  // parallelogram's offset (a change point, where the run stops), so 0.6 s of it.
  config.duration = 0.6;
  config.qd0 = Eigen::VectorXd::Zero(8);
  config.qd0(JointIndex(sdf.model, "axis1")) = 1.0;
  const RunResult result = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_EQ(result.stats.formulation, "joint");
  EXPECT_EQ(result.stats.loops.mobility, 4);
  EXPECT_LT(result.stats.energy_error_max, 1e-7);
  EXPECT_LT(result.stats.drift_position_max, 1e-10);
  const ToolWorst worst = WorstOf(sdf.model, result);
  EXPECT_GT(worst.drop, 0.05);  // it falls
  EXPECT_LT(worst.tilt, 1e-8);
}

}  // namespace
}  // namespace mbstream

// Driven mechanisms through singular poses (server/sim/singular_pose.h): a crank drives a
// slider-crank through its dead centres (passes: the crank still determines the mechanism);
// a slider drives it into one, a crank a parallelogram into its change point (the kinematic
// run stops, naming the time and the pose; the joint-space ODE either stops saying so or,
// where its momentum carries it, passes on its branch).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "server/parse/sdf_import.h"
#include "server/sim/loop_run.h"

namespace mbstream {
namespace {

const std::string kDir = std::string(MBSTREAM_SOURCE_DIR) + "/models/linkages/";

DriveConfig Line(double rate) {
  DriveConfig drive;
  drive.kind = DriveConfig::Kind::kPrescribed;
  drive.trajectory.kind = Trajectory::Kind::kSpline;
  drive.trajectory.times = {-1.0, 3.0};
  drive.trajectory.values = {-rate, 3.0 * rate};
  return drive;
}

DriveConfig Sine(double amplitude, double omega, double phase) {
  DriveConfig drive;
  drive.kind = DriveConfig::Kind::kPrescribed;
  drive.trajectory.amplitude = {amplitude};
  drive.trajectory.omega = {omega};
  drive.trajectory.phase = {phase};
  return drive;
}

RunConfig Config(int n) {
  RunConfig config;
  config.duration = 2.0;
  config.output_interval = 0.01;
  config.rtol = 1e-10;
  config.atol = 1e-12;
  config.drives.assign(static_cast<size_t>(n), DriveConfig{});
  return config;
}

double MaxDifference(const RunResult& r, int a, int b, double sign) {
  double worst = 0.0;
  for (int k = 0; k < r.num_frames(); ++k) {
    worst = std::max(worst, std::abs(r.q[r.num_dofs * k + a] - sign * r.q[r.num_dofs * k + b]));
  }
  return worst;
}

// A crank turning once a second takes the slider-crank through both dead centres (crank and
// rod in line, at t = 0.25 s and 0.75 s): the crank still determines every joint there, so
// the run passes, the loop held to round-off (LoopRunTest checks x against the closed form).
TEST(DeadCentreTest, ACrankDrivesTheSliderCrankThroughItsDeadCentres) {
  const SdfImport sdf = ImportSdfFile(kDir + "slider_crank.sdf");
  RunConfig config = Config(3);
  config.drives[0] = Line(2.0 * M_PI);
  const RunResult result = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_EQ(result.stats.formulation, "kinematic");
  EXPECT_NEAR(result.q[result.num_dofs * (result.num_frames() - 1)], 4.0 * M_PI, 1e-12);
  EXPECT_LT(result.stats.drift_position_max, 1e-12);
}

// The slider driven from the drawn pose to its outer dead centre (x = r + l at t = 1 s): there
// the slider no longer determines the crank, which could go on or turn back. Both the
// kinematic and the joint-space run stop before it, saying when and at which pose.
TEST(DeadCentreTest, ASliderDrivenToItsDeadCentreStopsSayingWhereAndWhen) {
  const SdfImport sdf = ImportSdfFile(kDir + "slider_crank.sdf");
  RunConfig config = Config(3);
  const double x0 = std::sqrt(0.3 * 0.3 - 0.1 * 0.1);  // rod 0.3 m, crank 0.1 m, crank up
  const double half = (0.4 - x0) / 2;
  config.drives[1] = Sine(half, M_PI, -M_PI / 2);  // q = half (1 - cos(pi t)): 0 to 0.4 - x0
  config.drives[1].trajectory.offset = half;
  const RunResult kinematic = SimulateLoops(sdf.model, sdf.loops, config);
  EXPECT_EQ(kinematic.stats.formulation, "kinematic");
  EXPECT_EQ(kinematic.stats.status, RunStatus::kFailed);
  EXPECT_NE(kinematic.stats.message.find("the driven mechanism reached a singular pose at t = "
                                         "0.99 s (crank_joint = -1.5"),
            std::string::npos)
      << kinematic.stats.message;
  EXPECT_NE(kinematic.stats.message.find("slider_joint = 0.117"), std::string::npos);
  EXPECT_NEAR(kinematic.stats.t_reached, 0.98, 1e-12);   // the last frame kept
  EXPECT_LT(kinematic.stats.drift_position_max, 1e-11);  // held to there

  config.formulation = Formulation::kJoint;
  const RunResult joint = SimulateLoops(sdf.model, sdf.loops, config);
  EXPECT_EQ(joint.stats.status, RunStatus::kFailed);
  EXPECT_NE(joint.stats.message.find("the loop constraints became singular at t = 0.99 s"),
            std::string::npos)
      << joint.stats.message;
  EXPECT_NE(joint.stats.message.find("(the pose: crank_joint = -1.5"), std::string::npos);
}

// The parallelogram's crank turned once a second reaches a change point at t = 1/6 s (every
// bar in line). Kinematically the drives no longer choose between the parallelogram and the
// antiparallelogram there: the run stops at the frame before, naming the step and the pose.
// The joint-space ODE carries the mechanism through by its momentum, on the parallelogram
// branch (rocker = crank, coupler level), the loop held to round-off.
TEST(DeadCentreTest, TheParallelogramsChangePointStopsADrivenPoseButNotTheDynamics) {
  const SdfImport sdf = ImportSdfFile(kDir + "parallelogram.sdf");
  RunConfig config = Config(3);
  config.drives[0] = Line(2.0 * M_PI);
  const RunResult kinematic = SimulateLoops(sdf.model, sdf.loops, config);
  EXPECT_EQ(kinematic.stats.status, RunStatus::kFailed);
  EXPECT_NE(kinematic.stats.message.find("the driven mechanism went through a singular pose "
                                         "between t = 0.16 s (crank_joint = 1.00531 rad, "
                                         "rocker_joint = 1.00531 rad, coupler_joint = -1.00531 "
                                         "rad) and t = 0.17 s"),
            std::string::npos)
      << kinematic.stats.message;
  EXPECT_EQ(kinematic.num_frames(), 17);
  EXPECT_LT(MaxDifference(kinematic, 1, 0, 1.0), 1e-12);  // on its branch up to there

  config.formulation = Formulation::kJoint;
  const RunResult joint = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(joint.stats.status, RunStatus::kFinished) << joint.stats.message;
  EXPECT_LT(MaxDifference(joint, 1, 0, 1.0), 1e-8);   // rocker = crank
  EXPECT_LT(MaxDifference(joint, 2, 0, -1.0), 1e-8);  // coupler level
  EXPECT_LT(joint.stats.drift_position_max, 1e-12);
  std::printf("joint-space ODE through the change points: branch %.3g rad, residual %.3g m\n",
              std::max(MaxDifference(joint, 1, 0, 1.0), MaxDifference(joint, 2, 0, -1.0)),
              joint.stats.drift_position_max);
}

}  // namespace
}  // namespace mbstream

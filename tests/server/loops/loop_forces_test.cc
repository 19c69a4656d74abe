// The cut joints' reactions (RunConfig::want_loop_forces, RunSpec.report_loop_forces):
// against the statics of the four-bar held still by its crank, the kinematic run's against
// the joint-space ODE's on the driven four-bar, the body formulations' against both, the
// results file's columns, the spec field, and the joint-space DAE's against the others.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>

#include "server/kinematics/forward_kinematics.h"
#include "server/model/data.h"
#include "server/parse/sdf_import.h"
#include "server/results/results_csv.h"
#include "server/sim/loop_run.h"
#include "server/spec/run_spec_json.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

const std::string kFourBar = std::string(MBSTREAM_SOURCE_DIR) + "/models/linkages/four_bar.sdf";
constexpr int kCrank = 0;

// The crank held at its drawn angle (a two-point spline, constant), or turned once a second.
DriveConfig Crank(double turns_per_second) {
  DriveConfig drive;
  drive.kind = DriveConfig::Kind::kPrescribed;
  drive.trajectory.kind = Trajectory::Kind::kSpline;
  drive.trajectory.times = {-1.0, 3.0};
  drive.trajectory.values = {-2.0 * M_PI * turns_per_second, 6.0 * M_PI * turns_per_second};
  return drive;
}

RunConfig CrankDriven(double turns_per_second, double duration) {
  RunConfig config;
  config.duration = duration;
  config.output_interval = 0.01;
  config.drives.assign(3, DriveConfig{});
  config.drives[kCrank] = Crank(turns_per_second);
  config.rtol = 1e-10;
  config.atol = 1e-12;
  config.want_loop_forces = true;
  return config;
}

// (r x F) . y: the moment about the joints' axis (-y or y: the sign does not matter for = 0).
double MomentY(const Vector3d& r, const Vector3d& force) { return r.cross(force).y(); }

// Held still, the coupler and the rocker are each in equilibrium under gravity, the pin at
// their proximal joint (the frame origin: no moment about its axis) and the cut joint's
// reaction: two moment equations, about each body's own pivot, fix the reaction's two
// components in the plane. Out of the plane (force along y, torques) the planar loop's
// redundant rows would carry them: statically indeterminate, reported as 0.
TEST(LoopForcesTest, TheFourBarHeldByItsCrankIsInEquilibrium) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  ASSERT_EQ(sdf.loops.size(), 1u);
  const RunResult result = SimulateLoops(sdf.model, sdf.loops, CrankDriven(0.0, 0.1));
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_EQ(result.stats.formulation, "kinematic");
  ASSERT_EQ(result.loop_force_names, std::vector<std::string>{"loop_joint"});
  ASSERT_EQ(result.loop_forces.size(), 6u * result.num_frames());

  const LoopClosure& loop = sdf.loops[0];
  ASSERT_NE(loop.body_a, kBase);
  ASSERT_NE(loop.body_b, kBase);
  Data data(sdf.model);
  ForwardKinematics(sdf.model, data, Eigen::VectorXd::Zero(3));  // drawn: closed, held there
  const Vector3d pin = data.X_world[loop.body_b].Apply(loop.X_BJ.p);
  const Vector3d gravity(0.0, 0.0, -9.81);
  const Eigen::Map<const Eigen::Matrix<double, 6, 1>> reaction(result.loop_forces.data());
  const Vector3d force_on_b = reaction.head<3>();
  double scale = 0.0;
  for (const auto& [body, force] :
       {std::pair{loop.body_b, force_on_b}, std::pair{loop.body_a, Vector3d(-force_on_b)}}) {
    const Pose& X = data.X_world[body];
    const Vector3d weight = sdf.model.bodies[body].inertia.mass * gravity;
    const double gravity_moment = MomentY(X.R * sdf.model.bodies[body].inertia.com, weight);
    scale = std::max(scale, std::abs(gravity_moment));
    EXPECT_NEAR(MomentY(pin - X.p, force) + gravity_moment, 0.0, 1e-10)
        << sdf.model.bodies[body].name;
  }
  EXPECT_GT(scale, 0.1);  // N*m: gravity does load the pin
  EXPECT_GT(force_on_b.norm(), 1.0);
  EXPECT_EQ(force_on_b.y(), 0.0);
  EXPECT_EQ(reaction.tail<3>().norm(), 0.0);
  // Held still, every frame says the same.
  for (int k = 1; k < result.num_frames(); ++k) {
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(result.loop_forces[6 * k + i], reaction(i), 1e-9);
  }
}

// The kinematic run's multipliers (least squares on the loop and drive rows, from inverse
// dynamics) and the joint-space ODE's (its acceleration-level solve) are computed apart;
// turning the crank once a second they agree frame by frame.
TEST(LoopForcesTest, TheOdeAndTheKinematicRunGiveTheSameReactions) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  RunConfig config = CrankDriven(1.0, 1.0);
  const RunResult kinematic = SimulateLoops(sdf.model, sdf.loops, config);
  config.formulation = Formulation::kJoint;
  const RunResult ode = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(kinematic.stats.status, RunStatus::kFinished) << kinematic.stats.message;
  ASSERT_EQ(ode.stats.status, RunStatus::kFinished) << ode.stats.message;
  ASSERT_EQ(ode.loop_forces.size(), kinematic.loop_forces.size());
  double worst = 0.0, largest = 0.0;
  for (size_t i = 0; i < ode.loop_forces.size(); ++i) {
    worst = std::max(worst, std::abs(ode.loop_forces[i] - kinematic.loop_forces[i]));
    largest = std::max(largest, std::abs(kinematic.loop_forces[i]));
  }
  std::printf("loop forces: largest %.4g N, ODE - kinematic %.3g N\n", largest, worst);
  EXPECT_GT(largest, 5.0);
  EXPECT_LT(worst, 1e-6 * largest);
}

TEST(LoopForcesTest, TheSpecFieldAsksAndTheFileNamesTheColumns) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  const std::vector<std::string> joints = {"crank_joint", "rocker_joint", "coupler_joint"};
  EXPECT_FALSE(ToRunConfig(ParseRunSpecJson("{}", "spec"), joints, "spec").want_loop_forces);
  RunConfig config =
      ToRunConfig(ParseRunSpecJson(R"({"report_loop_forces": true, "duration_s": 0.05})", "spec"),
                  joints, "spec");
  EXPECT_TRUE(config.want_loop_forces);
  config.formulation = Formulation::kJoint;
  config.rtol = 1e-8;
  config.atol = 1e-10;
  const RunResult result = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  bool found = false;
  for (const results_csv::Series& series : results_csv::SeriesOf(result)) {
    if (series.file != "loop_forces.csv") continue;
    found = true;
    EXPECT_EQ(series.header,
              "t,loop_joint.fx,loop_joint.fy,loop_joint.fz,loop_joint.tx,loop_joint.ty,"
              "loop_joint.tz");
    EXPECT_EQ(series.width, 6);
  }
  EXPECT_TRUE(found);
  config.want_loop_forces = false;
  for (const results_csv::Series& series :
       results_csv::SeriesOf(SimulateLoops(sdf.model, sdf.loops, config))) {
    EXPECT_NE(series.file, "loop_forces.csv");
  }
}

// The largest difference of two runs' reactions, relative to the largest reaction of `a`,
// which must exceed `at_least` (N or N*m).
double RelativeDifference(const RunResult& a, const RunResult& b, const char* what,
                          double at_least) {
  EXPECT_EQ(a.loop_forces.size(), b.loop_forces.size()) << what;
  if (a.loop_forces.size() != b.loop_forces.size()) return 1.0;
  double worst = 0.0, largest = 0.0;
  for (size_t i = 0; i < a.loop_forces.size(); ++i) {
    worst = std::max(worst, std::abs(a.loop_forces[i] - b.loop_forces[i]));
    largest = std::max(largest, std::abs(a.loop_forces[i]));
  }
  std::printf("%s: largest %.4g, difference %.3g (%.2g of it)\n", what, largest, worst,
              worst / largest);
  EXPECT_GT(largest, at_least) << what;
  return worst / largest;
}

// In body coordinates the reactions are the cut rows' multipliers acting on the child body
// (readout's acceleration-level solve), moved to the joint point: the same as the joint
// space's, the driven four-bar's against the kinematic run, the passive Delta's (five ball
// joints, three-dimensional) against the joint-space ODE.
TEST(LoopForcesTest, TheBodyFormulationsGiveTheJointSpaceReactions) {
  const SdfImport four_bar = ImportSdfFile(kFourBar);
  RunConfig config = CrankDriven(1.0, 1.0);
  config.rtol = 1e-9;
  config.atol = 1e-11;
  const RunResult kinematic = SimulateLoops(four_bar.model, four_bar.loops, config);
  ASSERT_EQ(kinematic.stats.status, RunStatus::kFinished) << kinematic.stats.message;
  for (const auto& [formulation, method] : {std::pair{Formulation::kBodyIndex2, Method::kIda},
                                            std::pair{Formulation::kBodyBaumgarte, Method::kBdf}}) {
    config.formulation = formulation;
    config.method = method;
    const RunResult body = SimulateLoops(four_bar.model, four_bar.loops, config);
    ASSERT_EQ(body.stats.status, RunStatus::kFinished) << body.stats.message;
    EXPECT_LT(RelativeDifference(kinematic, body, FormulationName(formulation), 5.0), 1e-6);
  }

  const SdfImport delta =
      ImportSdfFile(std::string(MBSTREAM_SOURCE_DIR) + "/models/linkages/delta.sdf");
  RunConfig passive;
  passive.duration = 0.1;
  passive.output_interval = 0.01;
  passive.drives.assign(delta.model.num_dofs(), DriveConfig{});
  passive.rtol = 1e-9;
  passive.atol = 1e-11;
  passive.want_loop_forces = true;
  passive.formulation = Formulation::kJoint;
  const RunResult joint = SimulateLoops(delta.model, delta.loops, passive);
  ASSERT_EQ(joint.stats.status, RunStatus::kFinished) << joint.stats.message;
  passive.formulation = Formulation::kBodyIndex2;
  passive.method = Method::kIda;
  const RunResult body = SimulateLoops(delta.model, delta.loops, passive);
  ASSERT_EQ(body.stats.status, RunStatus::kFinished) << body.stats.message;
  EXPECT_LT(RelativeDifference(joint, body, "Delta body-index2", 0.05), 1e-6);
}

// The joint space's GGL DAE (method ida at rtol 1e-9) gives its reactions from lambda's loop
// rows: the same, to the DAE's accuracy (measured 2026-11-27: 6.7e-7 of the largest driven,
// 3.5e-7 passive; 8e-5 and 1e-5 at rtol 1e-7, the tightest IDA's Newton converged at before
// the multipliers got tolerances of their own),
// as the kinematic run's (driven four-bar) and the joint-space ODE's and the body DAE's
// (passive four-bar).
TEST(LoopForcesTest, TheJointSpaceDaeGivesTheSameReactions) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  RunConfig config = CrankDriven(1.0, 1.0);
  const RunResult kinematic = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(kinematic.stats.status, RunStatus::kFinished) << kinematic.stats.message;
  config.formulation = Formulation::kJoint;
  config.method = Method::kIda;
  config.rtol = 1e-9;
  config.atol = 1e-11;
  ValidateLoopRun(sdf.model, sdf.loops, config);  // no longer refused
  const RunResult dae = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(dae.stats.status, RunStatus::kFinished) << dae.stats.message;
  EXPECT_EQ(dae.loop_force_names, kinematic.loop_force_names);
  EXPECT_LT(RelativeDifference(kinematic, dae, "driven: joint ida", 5.0), 3e-6);  // 6.7e-7

  RunConfig passive = CrankDriven(0.0, 0.5);
  passive.drives[kCrank] = DriveConfig{};
  passive.formulation = Formulation::kJoint;
  passive.method = Method::kIda;
  passive.rtol = 1e-9;
  passive.atol = 1e-11;
  const RunResult passive_dae = SimulateLoops(sdf.model, sdf.loops, passive);
  ASSERT_EQ(passive_dae.stats.status, RunStatus::kFinished) << passive_dae.stats.message;
  passive.method = Method::kBdf;
  const RunResult ode = SimulateLoops(sdf.model, sdf.loops, passive);
  ASSERT_EQ(ode.stats.status, RunStatus::kFinished) << ode.stats.message;
  EXPECT_LT(RelativeDifference(ode, passive_dae, "passive: joint ida vs bdf", 1.0), 2e-6);
  passive.formulation = Formulation::kBodyIndex2;
  passive.method = Method::kIda;
  const RunResult body = SimulateLoops(sdf.model, sdf.loops, passive);
  ASSERT_EQ(body.stats.status, RunStatus::kFinished) << body.stats.message;
  EXPECT_LT(RelativeDifference(body, passive_dae, "passive: joint ida vs body-index2", 1.0), 2e-6);
}

}  // namespace
}  // namespace mbstream

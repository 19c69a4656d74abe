// Runs of the shipped linkages against their closed-form position analysis, energy
// conservation and each other (kinematic against joint formulation); the errors a closed
// loop can raise; no allocation in the closed-loop ODE's steps.
#include "server/sim/loop_run.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "server/engine/engine.h"
#include "server/parse/sdf_import.h"
#include "server/sim/closed_loop_dae.h"
#include "server/sim/closed_loop_ode.h"
#include "server/sim/loop_plan.h"
#include "server/spec/run_spec_json.h"
#include "shared/common/check.h"
#include "tests/common/allocation_counter.h"

namespace mbstream {
namespace {

const std::string kFourBar = std::string(MBSTREAM_SOURCE_DIR) + "/models/linkages/four_bar.sdf";
const std::string kSliderCrank =
    std::string(MBSTREAM_SOURCE_DIR) + "/models/linkages/slider_crank.sdf";
const std::string kParallelogram =
    std::string(MBSTREAM_SOURCE_DIR) + "/models/linkages/parallelogram.sdf";

// The linkages' dimensions (models/linkages/generate.py), m; joint order of the tree.
constexpr double kA = 0.1, kB = 0.35, kC = 0.3,
                 kD = 0.4;                          // four-bar: crank, coupler, rocker, ground
constexpr double kR = 0.1, kL = 0.3;                // slider-crank: crank, rod
constexpr int kCrank = 0, kSecond = 1, kThird = 2;  // crank; rocker or slider; coupler or rod

double Wrap(double angle) { return std::remainder(angle, 2.0 * M_PI); }

// Four-bar: the closed-form loop closure for crank angle theta2 (from +x towards +z): B on the
// circles about A (radius b) and O4 (radius c), on the left of A -> O4 as drawn. Returns
// (coupler angle theta3, rocker angle theta4), absolute.
std::pair<double, double> FourBarAngles(double theta2) {
  const double ax = kA * std::cos(theta2), az = kA * std::sin(theta2);
  const double dx = kD - ax, dz = -az, d = std::hypot(dx, dz);
  const double along = (kB * kB - kC * kC + d * d) / (2.0 * d);
  const double h = std::sqrt(kB * kB - along * along);
  const double bx = ax + along * dx / d - h * dz / d, bz = az + along * dz / d + h * dx / d;
  return {std::atan2(bz - az, bx - ax), std::atan2(bz, bx - kD)};
}

// The four-bar's joint coordinates (crank, rocker, coupler) for crank coordinate q_crank.
Eigen::Vector3d FourBarJoints(double q_crank) {
  const double theta2_0 = M_PI / 2;
  const auto [theta3_0, theta4_0] = FourBarAngles(theta2_0);
  const double theta2 = theta2_0 + q_crank;
  const auto [theta3, theta4] = FourBarAngles(theta2);
  return {q_crank, Wrap(theta4 - theta4_0), Wrap((theta3 - theta2) - (theta3_0 - theta2_0))};
}

// Slider-crank: x = r cos(theta) + sqrt(l^2 - r^2 sin^2(theta)) and its rate.
double SliderX(double theta) {
  return kR * std::cos(theta) + std::sqrt(kL * kL - std::pow(kR * std::sin(theta), 2));
}
double SliderXRate(double theta, double theta_dot) {
  const double s = std::sin(theta), c = std::cos(theta);
  return -kR * s * theta_dot - kR * kR * s * c * theta_dot / std::sqrt(kL * kL - kR * kR * s * s);
}

DriveConfig CrankAtOneTurnPerSecond() {
  DriveConfig drive;
  drive.kind = DriveConfig::Kind::kPrescribed;
  drive.trajectory.kind = Trajectory::Kind::kSpline;
  // A two-point spline is a straight line; it is held constant outside its span (its rate
  // 0 at the ends), so the span covers the runs' 2 s with room on both sides.
  drive.trajectory.times = {-1.0, 3.0};
  drive.trajectory.values = {-2.0 * M_PI, 6.0 * M_PI};
  return drive;
}

RunConfig BaseConfig(int n) {
  RunConfig config;
  config.duration = 2.0;
  config.output_interval = 0.01;
  config.drives.assign(n, DriveConfig{});
  config.rtol = 1e-10;
  config.atol = 1e-12;
  return config;
}

// A linkage of models/linkages/ and one of its run specs ("-driven.json", "-passive.json").
struct Linkage {
  SdfImport sdf;
  std::vector<std::string> joints;  // the tree's, for ToRunConfig
};

Linkage LoadLinkage(const std::string& name) {
  Linkage linkage{
      ImportSdfFile(std::string(MBSTREAM_SOURCE_DIR) + "/models/linkages/" + name + ".sdf"), {}};
  for (const Body& body : linkage.sdf.model.bodies) linkage.joints.push_back(body.joint.name);
  return linkage;
}

RunConfig LinkageSpec(const Linkage& linkage, const std::string& name, const std::string& kind) {
  const std::string file = name + kind;
  return ToRunConfig(LoadRunSpecFile(std::string(MBSTREAM_SOURCE_DIR) + "/models/linkages/" + file),
                     linkage.joints, file);
}

TEST(LoopRunTest, KinematicFourBarFollowsTheClosedFormLoopClosure) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  RunConfig config = BaseConfig(3);
  config.drives[kCrank] = CrankAtOneTurnPerSecond();
  const RunResult result = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_EQ(result.stats.formulation, "kinematic");
  EXPECT_EQ(result.stats.loops.cut_joints, std::vector<std::string>{"loop_joint (revolute)"});
  EXPECT_EQ(result.stats.loops.equations, 5);
  EXPECT_EQ(result.stats.loops.independent, 2);
  EXPECT_EQ(result.stats.loops.mobility, 1);
  ASSERT_EQ(result.num_frames(), 201);
  double worst = 0.0, worst_rate = 0.0;
  for (int k = 0; k < result.num_frames(); ++k) {
    const double q_crank = result.q[result.num_dofs * k + kCrank];
    EXPECT_NEAR(q_crank, 2.0 * M_PI * result.t[k], 1e-12);
    const Eigen::Vector3d expected = FourBarJoints(q_crank);
    for (int j = 0; j < 3; ++j) {
      worst = std::max(worst, std::abs(Wrap(result.q[result.num_dofs * k + j] - expected(j))));
    }
    // The rocker's rate against central differences of the closed form.
    const double h = 1e-6;
    const double rate =
        (FourBarJoints(q_crank + h)(kSecond) - FourBarJoints(q_crank - h)(kSecond)) / (2.0 * h) *
        2.0 * M_PI;
    worst_rate = std::max(worst_rate, std::abs(result.qd[result.num_dofs * k + kSecond] - rate));
  }
  EXPECT_LT(worst, 1e-11);
  EXPECT_LT(worst_rate, 1e-6);
  EXPECT_LT(result.stats.drift_position_max, 1e-12);
  EXPECT_LT(result.stats.drift_velocity_max, 1e-12);
  EXPECT_EQ(result.stats.trust, Trust::kOk);
}

TEST(LoopRunTest, KinematicSliderCrankFollowsTheClosedForm) {
  const SdfImport sdf = ImportSdfFile(kSliderCrank);
  RunConfig config = BaseConfig(3);
  config.drives[kCrank] = CrankAtOneTurnPerSecond();
  const RunResult result = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_EQ(result.stats.formulation, "kinematic");
  const double x0 = SliderX(M_PI / 2);
  double worst = 0.0, worst_rate = 0.0;
  for (int k = 0; k < result.num_frames(); ++k) {
    const double theta = M_PI / 2 + result.q[result.num_dofs * k + kCrank];
    worst =
        std::max(worst, std::abs(result.q[result.num_dofs * k + kSecond] - (SliderX(theta) - x0)));
    worst_rate = std::max(worst_rate, std::abs(result.qd[result.num_dofs * k + kSecond] -
                                               SliderXRate(theta, 2.0 * M_PI)));
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_LT(worst_rate, 1e-11);
  // The slider's stroke is 2 r.
  double lo = 1e9, hi = -1e9;
  for (int k = 0; k < result.num_frames(); ++k) {
    lo = std::min(lo, result.q[result.num_dofs * k + kSecond]);
    hi = std::max(hi, result.q[result.num_dofs * k + kSecond]);
  }
  EXPECT_NEAR(hi - lo, 2.0 * kR, 1e-4);
}

TEST(LoopRunTest, ParallelogramKeepsItsCouplerParallelToTheGround) {
  const SdfImport sdf = ImportSdfFile(kParallelogram);
  RunConfig config = BaseConfig(3);
  // The crank swings -60 +- 40 degrees, clear of the change points at 0 and -180 degrees
  // where the bars line up and the loop's rank drops.
  config.drives[kCrank].kind = DriveConfig::Kind::kPrescribed;
  config.drives[kCrank].trajectory.amplitude = {0.7};
  config.drives[kCrank].trajectory.omega = {M_PI};
  config.drives[kCrank].trajectory.phase = {0.0};
  const RunResult result = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_EQ(result.stats.loops.independent, 2);
  EXPECT_EQ(result.stats.loops.mobility, 1);
  double worst = 0.0;
  for (int k = 0; k < result.num_frames(); ++k) {
    const double crank = result.q[result.num_dofs * k + kCrank];
    worst = std::max(worst,
                     std::abs(result.q[result.num_dofs * k + kSecond] - crank));  // rocker = crank
    worst =
        std::max(worst, std::abs(result.q[result.num_dofs * k + kThird] + crank));  // coupler level
  }
  EXPECT_LT(worst, 1e-12);
  // Released from rest as drawn, it swings with its energy kept.
  const RunResult passive = SimulateLoops(sdf.model, sdf.loops, BaseConfig(3));
  ASSERT_EQ(passive.stats.status, RunStatus::kFinished) << passive.stats.message;
  EXPECT_LT(passive.stats.energy_error_max, 1e-7);
  EXPECT_LT(passive.stats.drift_position_max, 1e-10);
}

TEST(LoopRunTest, TheCutJointsCoordinatesCloseThePlanarLoopsAngles) {
  // Every axis of the four-bar is -y: the coupler's absolute angle is crank + coupler on one
  // side of the loop and rocker - loop_joint on the other (loop_joint: coupler -> rocker),
  // so crank + coupler + loop_joint - rocker stays 0, and so do its rates. Likewise the
  // slider-crank's crank + rod + pin (the slider does not turn).
  const SdfImport four_bar = ImportSdfFile(kFourBar);
  const RunResult result = SimulateLoops(four_bar.model, four_bar.loops, BaseConfig(3));
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  ASSERT_EQ(result.num_dofs, 4);
  EXPECT_EQ(result.joint_names, (std::vector<std::string>{"crank_joint", "rocker_joint",
                                                          "coupler_joint", "loop_joint"}));
  double worst = 0.0, worst_rate = 0.0, travel = 0.0;
  for (int k = 0; k < result.num_frames(); ++k) {
    const double* q = &result.q[4 * k];
    const double* qd = &result.qd[4 * k];
    worst = std::max(worst, std::abs(q[kCrank] + q[kThird] + q[3] - q[kSecond]));
    worst_rate = std::max(worst_rate, std::abs(qd[kCrank] + qd[kThird] + qd[3] - qd[kSecond]));
    travel = std::max(travel, std::abs(q[3]));
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(worst_rate, 1e-7);
  EXPECT_GT(travel, 0.1);  // the cut joint turns

  const SdfImport slider = ImportSdfFile(kSliderCrank);
  RunConfig config = BaseConfig(3);
  config.drives[kCrank] = CrankAtOneTurnPerSecond();
  const RunResult driven = SimulateLoops(slider.model, slider.loops, config);
  ASSERT_EQ(driven.stats.status, RunStatus::kFinished) << driven.stats.message;
  ASSERT_EQ(driven.num_dofs, 4);
  EXPECT_EQ(driven.joint_names.back(), "pin_joint");
  ASSERT_EQ(driven.tau.size(), driven.q.size());  // the cut joint's effort column: 0
  double slider_worst = 0.0, last = 0.0, largest_step = 0.0;
  for (int k = 0; k < driven.num_frames(); ++k) {
    const double* q = &driven.q[4 * k];
    slider_worst = std::max(slider_worst, std::abs(q[kCrank] + q[kThird] + q[3]));
    if (k > 0) largest_step = std::max(largest_step, std::abs(q[3] - last));
    last = q[3];
    EXPECT_EQ(driven.tau[4 * k + 3], 0.0);
  }
  // Two crank turns: the pin's angle comes back each turn, without jumps of 2 pi.
  EXPECT_LT(slider_worst, 1e-9);
  EXPECT_LT(largest_step, 0.1);
}

TEST(LoopRunTest, TheCrankTorqueDoesTheWorkTheFourBarGains) {
  // The prescribed crank's effort comes from the multipliers; the energy balance
  // E(t) - E(0) = integral of effort * rate (trapezoid over 1 ms frames) checks it.
  const SdfImport sdf = ImportSdfFile(kFourBar);
  RunConfig config = BaseConfig(3);
  config.drives[kCrank] = CrankAtOneTurnPerSecond();
  config.formulation = Formulation::kJoint;
  config.output_interval = 0.001;
  const RunResult result = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_LT(result.stats.energy_error_max, 1e-5);
  EXPECT_GT(result.stats.energy_error_max, 0.0);
}

TEST(LoopRunTest, PassiveFourBarConservesEnergyAndStaysClosed) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  const RunConfig config = BaseConfig(3);  // every joint passive, released at rest as drawn
  const RunResult result = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_EQ(result.stats.formulation, "joint");
  EXPECT_EQ(result.stats.integrator, "CVODE BDF with projection");
  EXPECT_GE(result.stats.energy_error_max, 0.0);
  EXPECT_LT(result.stats.energy_error_max, 1e-7);
  EXPECT_LT(result.stats.drift_position_max, 1e-10);
  EXPECT_LT(result.stats.drift_velocity_max, 1e-8);
  // It moves, and its rocker and coupler stay where the crank's loop closure puts them.
  double travel = 0.0, worst = 0.0;
  for (int k = 0; k < result.num_frames(); ++k) {
    travel = std::max(travel, std::abs(result.q[result.num_dofs * k + kCrank]));
    const Eigen::Vector3d expected = FourBarJoints(result.q[result.num_dofs * k + kCrank]);
    for (int j = 1; j < 3; ++j)
      worst = std::max(worst, std::abs(Wrap(result.q[result.num_dofs * k + j] - expected(j))));
  }
  EXPECT_GT(travel, 0.5);
  EXPECT_LT(worst, 1e-9);
}

TEST(LoopRunTest, PassiveSliderCrankConservesEnergy) {
  const SdfImport sdf = ImportSdfFile(kSliderCrank);
  RunConfig config = BaseConfig(3);
  config.qd0 = Eigen::Vector3d(6.0, 0.0, 0.0);  // a spin of the crank; the rest follows
  const RunResult result = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_LT(result.stats.energy_error_max, 1e-7);
  const double x0 = SliderX(M_PI / 2);
  double worst = 0.0;
  for (int k = 0; k < result.num_frames(); ++k) {
    const double theta = M_PI / 2 + result.q[result.num_dofs * k + kCrank];
    worst =
        std::max(worst, std::abs(result.q[result.num_dofs * k + kSecond] - (SliderX(theta) - x0)));
  }
  EXPECT_LT(worst, 1e-10);
}

TEST(LoopRunTest, GglDaeWithIdaAgreesWithTheProjectedOde) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  const RunResult ode = SimulateLoops(sdf.model, sdf.loops, BaseConfig(3));
  // At the ODE's tolerances (rtol 1e-10): the multipliers' tolerances of their own
  // (ClosedLoopDae::AbsoluteTolerances) let IDA's Newton converge there.
  RunConfig config = BaseConfig(3);
  config.method = Method::kIda;
  const RunResult dae = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(dae.stats.status, RunStatus::kFinished) << dae.stats.message;
  EXPECT_EQ(dae.stats.integrator, "IDA (dense) (index-2 GGL)");
  EXPECT_NE(dae.stats.formulation_reason.find("Gear, Gupta and Leimkuhler"), std::string::npos);
  EXPECT_EQ(dae.stats.equations, 2 * 3 + 2 * 2);
  EXPECT_LT(dae.stats.energy_error_max, 1e-8);     // 3.1e-9 (1.5e-6 at rtol 1e-7)
  EXPECT_LT(dae.stats.drift_position_max, 1e-11);  // 3.2e-12
  EXPECT_LT(dae.stats.drift_velocity_max, 1e-9);   // 2.2e-10
  ASSERT_EQ(dae.num_frames(), ode.num_frames());
  double worst = 0.0;
  for (size_t i = 0; i < dae.q.size(); ++i) worst = std::max(worst, std::abs(dae.q[i] - ode.q[i]));
  EXPECT_LT(worst, 1e-5);  // 1.7e-6 over the 2 s
  EXPECT_GT(worst, 0.0);
}

// Every shipped linkage released as its passive spec says, by the GGL DAE at tight
// tolerances: until the multipliers got tolerances of their own (ClosedLoopDae::
// AbsoluteTolerances), IDA's Newton stopped converging within the first steps at rtol 1e-9 on
// every one of them (on the Delta already at 1e-7). Each run against the projected ODE at
// rtol 1e-10: the final joint values, closer as the tolerance tightens.
TEST(LoopRunTest, TheGglDaeRunsEveryPassiveLinkageAtTightTolerances) {
  for (const std::string name :
       {"four_bar", "parallelogram", "slider_crank", "delta", "palletiser"}) {
    const Linkage linkage = LoadLinkage(name);
    const SdfImport& sdf = linkage.sdf;
    RunConfig config = LinkageSpec(linkage, name, "-passive.json");
    config.duration = std::min(config.duration, 1.0);
    config.formulation = Formulation::kJoint;
    config.method = Method::kBdf;
    config.rtol = 1e-10;
    config.atol = 1e-12;
    const RunResult ode = SimulateLoops(sdf.model, sdf.loops, config);
    ASSERT_EQ(ode.stats.status, RunStatus::kFinished) << name << ": " << ode.stats.message;
    double loosest = 0.0;  // the error at rtol 1e-7
    for (const double rtol : {1e-7, 1e-9, 1e-10}) {
      SCOPED_TRACE(name + " at rtol " + std::to_string(rtol));
      config.method = Method::kIda;
      config.rtol = rtol;
      config.atol = rtol / 100;
      const RunResult dae = SimulateLoops(sdf.model, sdf.loops, config);
      ASSERT_EQ(dae.stats.status, RunStatus::kFinished) << dae.stats.message;
      ASSERT_EQ(dae.num_frames(), ode.num_frames());
      const size_t last = static_cast<size_t>(ode.num_frames() - 1) * ode.num_dofs;
      double worst = 0.0;
      for (int j = 0; j < ode.num_dofs; ++j) {
        worst = std::max(worst, std::abs(dae.q[last + j] - ode.q[last + j]));
      }
      // The DAE's global error over the run (passive four-bar, 1 s: 6e-5 at 1e-7, 4.7e-6 at
      // 1e-9, 8.7e-8 at 1e-10), down to the reference's own near 1e-7.
      EXPECT_LT(worst, std::max(1e4 * rtol, 1e-6));
      if (rtol == 1e-7) loosest = worst;
      if (rtol == 1e-10) {
        EXPECT_LT(worst, loosest / 10);
      }
      EXPECT_LT(dae.stats.drift_position_max, 1e3 * rtol);
    }
  }
}

TEST(LoopRunTest, DrivenCrankByTheOdeMatchesTheKinematicRun) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  RunConfig config = BaseConfig(3);
  config.drives[kCrank] = CrankAtOneTurnPerSecond();
  const RunResult kinematic = SimulateLoops(sdf.model, sdf.loops, config);
  config.formulation = Formulation::kJoint;
  const RunResult ode = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(ode.stats.status, RunStatus::kFinished) << ode.stats.message;
  EXPECT_EQ(ode.stats.formulation, "joint");
  ASSERT_EQ(ode.num_frames(), kinematic.num_frames());
  double worst_q = 0.0, worst_tau = 0.0, largest_tau = 0.0;
  for (size_t i = 0; i < ode.q.size(); ++i) {
    worst_q = std::max(worst_q, std::abs(ode.q[i] - kinematic.q[i]));
    worst_tau = std::max(worst_tau, std::abs(ode.tau[i] - kinematic.tau[i]));
    largest_tau = std::max(largest_tau, std::abs(kinematic.tau[i]));
  }
  EXPECT_LT(worst_q, 1e-8);
  EXPECT_GT(largest_tau, 0.5);  // the crank's torque (gravity and inertia) is not trivial
  EXPECT_LT(worst_tau, 1e-6 * largest_tau);
}

TEST(LoopRunTest, BaumgarteAloneHoldsTheLoopWithoutProjection) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  RunConfig config = BaseConfig(3);
  config.method = Method::kAdams;
  config.rtol = 1e-8;
  config.atol = 1e-10;
  const RunResult result = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_EQ(result.stats.integrator, "CVODE Adams");
  EXPECT_LT(result.stats.drift_position_max, 1e-6);
  EXPECT_GT(result.stats.drift_position_max, 0.0);
}

TEST(LoopRunTest, AnUnassembledStartIsAssembledNearTheGivenPose) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  RunConfig config = BaseConfig(3);
  config.duration = 0.1;
  config.q0 = Eigen::Vector3d(0.2, 0.0, 0.0);
  const RunResult result = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_NE(result.stats.loops.assembly.find("assembled by Newton"), std::string::npos)
      << result.stats.loops.assembly;
  EXPECT_LT(result.stats.drift_position_max, 1e-10);
  EXPECT_GT(std::abs(result.q[kSecond]), 0.01);  // the rocker moved to close the loop
}

void ExpectRefused(const SdfImport& sdf, const RunConfig& config, const std::string& words) {
  try {
    ValidateLoopRun(sdf.model, sdf.loops, config);
    ADD_FAILURE() << "accepted; expected: " << words;
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(words), std::string::npos) << error.what();
  }
}

TEST(LoopRunTest, RefusesWhatTheLoopsCannotRun) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  RunConfig config = BaseConfig(3);
  config.formulation = Formulation::kKinematic;
  ExpectRefused(sdf, config, "the mechanism has 1 (5 loop equation(s), 2 independent, mobility 1)");
  config = BaseConfig(3);
  config.drives[kCrank] = CrankAtOneTurnPerSecond();
  config.drives[kSecond] = CrankAtOneTurnPerSecond();
  ExpectRefused(sdf, config, "the loops already fix some of them");
  config = BaseConfig(3);
  config.formulation = Formulation::kBodyIndex3;
  config.method = Method::kIda;
  ExpectRefused(sdf, config, "formulation body-index3 does not close kinematic loops");
}

TEST(LoopRunTest, ALoopThatCannotCloseNamesItsJointAndLine) {
  // Crank 0.3 m, coupler 1.02 m, rocker 0.1 m, ground 1 m: with the crank held pointing
  // away from the rocker (q = pi/2), its pin is 1.3 m from the rocker's pivot, beyond the
  // coupler and rocker's reach (1.12 m).
  const std::string text = R"(<?xml version="1.0"?>
<sdf version="1.7">
  <model name="broken">
    <link name="crank"><pose>0 0 0 0 -1.5707963267948966 0</pose></link>
    <link name="coupler"><pose>0 0 0.3 0 0 0</pose></link>
    <link name="rocker"><pose>1 0 0 0 -1.5707963267948966 0</pose></link>
    <joint name="crank_joint" type="revolute"><parent>world</parent><child>crank</child>
      <axis><xyz>0 -1 0</xyz></axis></joint>
    <joint name="rocker_joint" type="revolute"><parent>world</parent><child>rocker</child>
      <axis><xyz>0 -1 0</xyz></axis></joint>
    <joint name="coupler_joint" type="revolute"><parent>crank</parent><child>coupler</child>
      <axis><xyz>0 -1 0</xyz></axis></joint>
    <joint name="loop_joint" type="revolute"><parent>coupler</parent><child>rocker</child>
      <pose>0.1 0 0 0 0 0</pose><axis><xyz>0 -1 0</xyz></axis></joint>
  </model>
</sdf>
)";
  const SdfImport sdf = ImportSdf(text, "broken.sdf");
  RunConfig config = BaseConfig(3);
  config.drives[kCrank].kind = DriveConfig::Kind::kPrescribed;
  config.drives[kCrank].trajectory.offset = M_PI / 2;
  ExpectRefused(sdf, config,
                "broken.sdf:13: joint 'loop_joint': the loop it closes cannot be assembled");
  config.drives[kCrank].trajectory.offset = 0.0;  // as drawn: it closes
  EXPECT_EQ(ValidateLoopRun(sdf.model, sdf.loops, config).formulation, Formulation::kKinematic);
}

TEST(LoopRunTest, TheClosedLoopOdeStepsWithoutAllocating) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  RunConfig config = BaseConfig(3);
  config.drives[kCrank] = CrankAtOneTurnPerSecond();
  const DriveSet drives(sdf.model, config.drives);
  ClosedLoopOde ode(sdf.model, sdf.loops, drives, Eigen::VectorXd::Zero(3), config.baumgarte,
                    1e-12);
  Eigen::VectorXd y(6), ydot(6), correction(6);
  y << 0.1, 0.05, -0.02, 6.0, 1.0, -1.0;
  const long before = testing::AllocationCount();
  const int rhs = ode.Rhs(0.01, y.data(), ydot.data());
  const int project = ode.Project(0.01, y.data(), correction.data());
  ASSERT_TRUE(ode.Evaluate(0.01, y.data()));
  const double conditioning = ode.ConstraintConditioning();  // checked at every frame
  EXPECT_EQ(testing::AllocationCount() - before, 0);
  EXPECT_EQ(rhs, 0);
  EXPECT_EQ(project, 0);
  EXPECT_TRUE(ydot.allFinite());
  EXPECT_GT(conditioning, 0.01);  // a four-bar far from its singular poses
  EXPECT_LE(conditioning, 1.0);
  // The projection puts the crank on its track (2 pi t) and closes the loop.
  EXPECT_NEAR(y(0) + correction(0), 2.0 * M_PI * 0.01, 1e-12);
  EXPECT_NEAR(y(3) + correction(3), 2.0 * M_PI, 1e-9);
}

TEST(LoopRunTest, TheGglResidualAllocatesNothing) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  RunConfig config = BaseConfig(3);
  config.drives[kCrank] = CrankAtOneTurnPerSecond();
  const DriveSet drives(sdf.model, config.drives);
  const LoopPlan plan = PlanLoopRun(sdf.model, sdf.loops, config, drives);
  ClosedLoopDae dae(sdf.model, sdf.loops, drives, plan.rank);
  Eigen::VectorXd y, yp, r(dae.size());
  dae.ConsistentStart(0.0, plan.q0, plan.qd0, &y, &yp);
  const long before = testing::AllocationCount();
  const int code = dae.Residual(0.0, y.data(), yp.data(), r.data());
  EXPECT_EQ(testing::AllocationCount() - before, 0);
  EXPECT_EQ(code, 0);
  EXPECT_LT(r.cwiseAbs().maxCoeff(), 1e-12);  // the start is consistent
}

// The engine's one entry (server/engine/engine.h) takes a model with loops to SimulateLoops:
// the same frames, bit for bit.
TEST(LoopRunTest, TheEngineEntryRunsAModelWithLoopsAsSimulateLoopsDoes) {
  const SdfImport sdf = ImportSdfFile(kSliderCrank);
  RunConfig config = BaseConfig(sdf.model.num_dofs());
  config.duration = 0.2;
  ASSERT_EQ(ValidateLoopRun(sdf.model, sdf.loops, config).formulation, Formulation::kJoint);
  const RunResult direct = SimulateLoops(sdf.model, sdf.loops, config);
  const RunResult entry = Simulate(sdf.model, sdf.loops, config);
  ASSERT_EQ(direct.stats.status, RunStatus::kFinished) << direct.stats.message;
  EXPECT_EQ(entry.stats.formulation, direct.stats.formulation);
  EXPECT_EQ(entry.t, direct.t);
  EXPECT_EQ(entry.q, direct.q);
  EXPECT_EQ(entry.qd, direct.qd);
}

// Every linkage of models/linkages/ ships a driven and a passive run spec (its scene script:
// tests/viewer/linkage_scene_test.cc): each loads and is accepted for its model; the
// parallelogram's, the newest, also run (0.5 s) to the end.
TEST(LoopRunTest, EveryLinkagesRunSpecsLoadAndAreAccepted) {
  for (const std::string name :
       {"four_bar", "parallelogram", "slider_crank", "delta", "palletiser"}) {
    const Linkage linkage = LoadLinkage(name);
    const SdfImport& sdf = linkage.sdf;
    for (const std::string kind : {"-driven.json", "-passive.json"}) {
      SCOPED_TRACE(name + kind);
      RunConfig config = LinkageSpec(linkage, name, kind);
      EXPECT_NO_THROW(ValidateLoopRun(sdf.model, sdf.loops, config));
      if (name != "parallelogram") continue;
      config.duration = 0.5;
      const RunResult result = Simulate(sdf.model, sdf.loops, config);
      EXPECT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
      EXPECT_LT(result.stats.drift_position_max, 1e-10);
    }
  }
}

}  // namespace
}  // namespace mbstream

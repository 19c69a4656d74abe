// Runs with an accuracy target: the choice (closed form, stiffness, pilots), the run and its
// verification, on the shipped scenes and on a model the choice was not developed on; the
// achieved errors are checked against independent tight reference runs, not only the choice's
// own check.

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "server/choose/frame_track.h"
#include "server/engine/engine.h"
#include "server/sim/simulate.h"
#include "tests/common/test_models.h"
#include "tests/server/sim/scene_fixture.h"

namespace mbstream {
namespace {

using testing::Irb1600;
using testing::Scene;

RunConfig WithTcpTarget(RunConfig config, double target) {
  config.target.tcp_error_m = target;
  config.method_auto = true;
  return config;
}

// The largest TCP distance of `result` from a tight run of `config` (method, rtol given).
double ErrorAgainstReference(const Model& model, RunConfig config, const RunResult& result,
                             Method method, double rtol) {
  config.target = AccuracyTarget{};
  config.method_auto = false;
  config.method = method;
  config.erk_table = "";
  config.rtol = rtol;
  config.atol = rtol / 100;
  config.max_steps = 0;
  config.max_cpu_s = 0;
  const RunResult reference = Simulate(model, config);
  EXPECT_EQ(reference.stats.status, RunStatus::kFinished) << reference.stats.message;
  return CompareTracks(TrackOf(result), TrackOf(reference)).tcp_m;
}

nlohmann::json Choice(const RunResult& result) {
  return nlohmann::json::parse(result.stats.choice_json);
}

TEST(ChooseTest, NoTargetIsAPlainRun) {
  RunConfig config = Scene("stiff-servo");
  const RunResult plain = Simulate(Irb1600(), config);
  EXPECT_TRUE(plain.stats.choice_json.empty());
  EXPECT_FALSE(plain.stats.target_met.has_value());
  // The engine's entry took the inner run's path: the same frames, bit for bit.
  const RunResult inner = SimulateTree(Irb1600(), config);
  EXPECT_EQ(plain.t, inner.t);
  EXPECT_EQ(plain.q, inner.q);
}

TEST(ChooseTest, EveryJointPrescribedIsTheClosedForm) {
  const RunResult result = Simulate(Irb1600(), WithTcpTarget(Scene("seed-run"), 1e-9));
  ASSERT_EQ(result.stats.status, RunStatus::kFinished);
  EXPECT_EQ(result.stats.formulation, "kinematic");
  ASSERT_TRUE(result.stats.target_met.has_value());
  EXPECT_TRUE(*result.stats.target_met);
  EXPECT_EQ(Choice(result)["pick"]["formulation"], "kinematic");
  EXPECT_DOUBLE_EQ(result.stats.tcp_error_max, 0.0);
}

TEST(ChooseTest, StiffServoPicksBdfAndMeetsItsTargets) {
  for (double target : {1e-5, 1e-8}) {
    const RunConfig config = WithTcpTarget(Scene("stiff-servo"), target);
    const RunResult result = Simulate(Irb1600(), config);
    ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
    EXPECT_EQ(result.stats.method, "bdf");
    const nlohmann::json choice = Choice(result);
    // The explicit methods are excluded by the stiffness probe, with its numbers.
    EXPECT_GT(choice["stiffness"]["eigenvalue_max_per_s"].get<double>(), 1e6);
    for (const auto& candidate : choice["candidates"]) {
      if (candidate["name"] == "erk") {
        EXPECT_FALSE(candidate["piloted"].get<bool>());
        EXPECT_NE(candidate["verdict"].get<std::string>().find("stability"), std::string::npos);
      }
    }
    ASSERT_TRUE(result.stats.target_met.has_value()) << result.stats.message;
    EXPECT_TRUE(*result.stats.target_met) << result.stats.message;
    const double achieved = choice["verification"]["achieved"]["tcp_m"].get<double>();
    EXPECT_LE(achieved, target);
    EXPECT_LE(ErrorAgainstReference(Irb1600(), config, result, Method::kBdf, 1e-12), target);
    // Run and check each go on from a pilot (the servos hold every joint): the looser pilot
    // for the run, the tighter for the check, both at the pilot span's end.
    const double span = choice["pilot"]["span_s"].get<double>();
    ASSERT_TRUE(choice["pick"].contains("continues_pilot")) << choice.dump(1);
    ASSERT_TRUE(choice["verification"].contains("continues_pilot")) << choice.dump(1);
    EXPECT_DOUBLE_EQ(choice["pick"]["continues_pilot"]["from_s"].get<double>(), span);
    EXPECT_DOUBLE_EQ(result.stats.continued_from_s, span);
    EXPECT_LT(choice["verification"]["continues_pilot"]["rtol"].get<double>(),
              choice["pick"]["continues_pilot"]["rtol"].get<double>());
  }
}

// The hidden-from-tuning side: a 7-joint arm of other masses whose wrist has a stiff servo.
TEST(ChooseTest, UnseenSevenJointArmWithStiffServoMeetsItsTargets) {
  const Model model = testing::SevenJointArm();
  RunConfig config;
  config.duration = 3.0;
  config.output_interval = 0.02;
  config.drives.resize(7);
  for (int i = 0; i < 7; ++i) {
    DriveConfig& drive = config.drives[i];
    drive.kind = DriveConfig::Kind::kPdServo;
    drive.kp = i == 6 ? 4e4 : 800.0 / (i + 1);
    drive.kd = i == 6 ? 400.0 : 60.0 / (i + 1);
    drive.trajectory.offset = 0.1 * i;
    drive.trajectory.amplitude = {0.6};
    drive.trajectory.omega = {1.5 + 0.3 * i};
    drive.trajectory.phase = {0.2 * i};
  }
  config.q0 = Eigen::VectorXd::Zero(7);
  for (double target : {1e-4, 1e-7}) {
    const RunConfig asked = WithTcpTarget(config, target);
    const RunResult result = Simulate(model, asked);
    ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
    ASSERT_TRUE(result.stats.target_met.has_value()) << result.stats.message;
    EXPECT_TRUE(*result.stats.target_met) << result.stats.message;
    EXPECT_LE(ErrorAgainstReference(model, asked, result, Method::kBdf, 1e-12), target)
        << result.stats.choice_json;
  }
}

// Whenever a target run reports its target met, an independent tight reference agrees; a
// miss is reported with its message, never accepted. Returns whether it was met.
bool ExpectNeverAcceptsAMiss(const Model& model, const RunConfig& asked) {
  const RunResult result = Simulate(model, asked);
  EXPECT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_TRUE(result.stats.target_met.has_value()) << result.stats.message;
  if (!result.stats.target_met.has_value()) return false;
  const double achieved = ErrorAgainstReference(model, asked, result, Method::kBdf, 1e-12);
  if (*result.stats.target_met) {
    EXPECT_LE(achieved, asked.target.tcp_error_m) << result.stats.choice_json;
  } else {
    EXPECT_NE(result.stats.message.find("target missed"), std::string::npos);
  }
  return *result.stats.target_met;
}

// A second model the choice was not developed on (added with the pilots' cost model and the
// check at a tenth of the target): a branching tree with a prismatic joint, skew axes and
// armature, its joints on soft PD servos, 2 s. 1e-7 m is met; at 1e-4 m the run (rtol 1.4e-4)
// ends 1.9e-4 m from the reference, its check says 1.05e-4 m: reported missed, not accepted.
TEST(ChooseTest, UnseenBranchingTreeOnServosMeetsATightTargetAndReportsItsMisses) {
  const Model model = testing::BranchingModel();
  RunConfig config;
  config.duration = 2.0;
  config.output_interval = 0.02;
  config.drives.resize(static_cast<size_t>(model.num_dofs()));
  for (int i = 0; i < model.num_dofs(); ++i) {
    DriveConfig& drive = config.drives[static_cast<size_t>(i)];
    drive.kind = DriveConfig::Kind::kPdServo;
    drive.kp = 300.0 / (i + 1);
    drive.kd = 20.0 / (i + 1);
    drive.trajectory.amplitude = {0.4};
    drive.trajectory.omega = {2.0 + 0.5 * i};
    drive.trajectory.phase = {0.0};
  }
  config.q0 = Eigen::VectorXd::Zero(model.num_dofs());
  ExpectNeverAcceptsAMiss(model, WithTcpTarget(config, 1e-4));
  EXPECT_TRUE(ExpectNeverAcceptsAMiss(model, WithTcpTarget(config, 1e-7)));
}

// The same tree released under gravity with no drive (damping on one joint only): its motion
// separates nearby trajectories faster than the pilot's first 0.1 s shows (the error grows
// some 200 times past the pilot, where the choice assumes 20), so the choice misses both
// targets here; the point is that the misses are reported, never accepted.
TEST(ChooseTest, UnseenPassiveTreeNeverAcceptsAMiss) {
  const Model model = testing::BranchingModel();
  RunConfig config;
  config.duration = 2.0;
  config.output_interval = 0.02;
  config.drives.resize(static_cast<size_t>(model.num_dofs()));  // passive
  config.q0 = Eigen::VectorXd::Constant(model.num_dofs(), 0.3);
  for (double target : {1e-4, 1e-7}) ExpectNeverAcceptsAMiss(model, WithTcpTarget(config, target));
}

TEST(ChooseTest, VerifyFalseSkipsTheCheck) {
  RunConfig config = WithTcpTarget(Scene("stiff-servo"), 1e-6);
  config.verify = false;
  const RunResult result = Simulate(Irb1600(), config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished);
  EXPECT_FALSE(result.stats.target_met.has_value());
  EXPECT_FALSE(Choice(result)["verification"]["ran"].get<bool>());
  EXPECT_NE(result.stats.message.find("not verified"), std::string::npos);
}

// A chaotic scene over 20 s: no double-precision run resolves a 1e-6 m TCP track; the run
// still FINISHES, with target_met false and a message naming the horizon.
TEST(ChooseTest, ChaoticTargetIsReportedMissedWithItsHorizon) {
  const RunResult result = Simulate(Irb1600(), WithTcpTarget(Scene("passive-swing"), 1e-6));
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  ASSERT_TRUE(result.stats.target_met.has_value());
  EXPECT_FALSE(*result.stats.target_met);
  EXPECT_NE(result.stats.message.find("target missed"), std::string::npos);
  EXPECT_NE(result.stats.message.find("agree within the target only up to t ="), std::string::npos)
      << result.stats.message;
}

}  // namespace
}  // namespace mbstream

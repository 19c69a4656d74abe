// The run spec's JSON form: the shipped scenes load with the values they document, the
// defaults apply, drives match joints by name or position, and RunConfig survives the trip
// through RunSpec and JSON unchanged.
#include "server/spec/run_spec_json.h"

#include <array>
#include <numbers>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "shared/common/check.h"

namespace mbstream {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

const std::vector<std::string> kJoints = {"joint1", "joint2", "joint3",
                                          "joint4", "joint5", "joint6"};

// The seed's sine law q_i = a_i sin(w0 t), computed here as the spec states it.
constexpr double kPi = std::numbers::pi;
constexpr double kW0 = kPi / 10.0;
constexpr std::array<double, 6> kA = {kPi, kPi / 3.0, 0.25 * kPi, kPi, 0.6 * kPi, kPi};

std::string ModelFile(const std::string& name) {
  return std::string(MBSTREAM_SOURCE_DIR) + "/models/irb1600/" + name;
}

RunConfig LoadScene(const std::string& name) {
  return ToRunConfig(LoadRunSpecFile(ModelFile(name)), kJoints, name);
}

std::string ErrorOf(const std::string& json) {
  try {
    ToRunConfig(ParseRunSpecJson(json, "test.json"), kJoints, "test.json");
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

// The seed's trajectory for joint i, bit for bit.
void ExpectSeedTrajectory(const Trajectory& trajectory, int i) {
  EXPECT_EQ(trajectory.kind, Trajectory::Kind::kSine);
  EXPECT_EQ(trajectory.offset, 0.0);
  ASSERT_EQ(trajectory.amplitude.size(), 1u);
  ASSERT_EQ(trajectory.omega.size(), 1u);
  ASSERT_EQ(trajectory.phase.size(), 1u);
  EXPECT_EQ(trajectory.amplitude[0], kA[i]) << "joint " << i + 1;
  EXPECT_EQ(trajectory.omega[0], kW0);
  EXPECT_EQ(trajectory.phase[0], 0.0);
}

TEST(RunSpecSceneTest, SeedRunIsTheSeedExperiment) {
  // The literals of the JSON file are the shortest round-trip forms of these doubles.
  EXPECT_EQ(kW0, 0.3141592653589793);
  EXPECT_EQ(kA[1], 1.0471975511965976);
  EXPECT_EQ(kA[2], 0.7853981633974483);
  EXPECT_EQ(kA[4], 1.8849555921538759);

  const RunConfig config = LoadScene("seed-run.json");
  EXPECT_EQ(config.duration, 20.0);
  EXPECT_EQ(config.output_interval, 0.05);
  EXPECT_EQ(config.max_step, 0.05);
  EXPECT_EQ(config.method, Method::kBdf);
  EXPECT_EQ(config.formulation, Formulation::kAuto);
  EXPECT_EQ(config.rtol, 1e-6);
  EXPECT_EQ(config.atol, 1e-8);
  EXPECT_EQ(config.gravity, Eigen::Vector3d(0.0, 0.0, -9.81));
  EXPECT_FALSE(config.want_torques);  // like the seed: states and TCP only
  EXPECT_EQ(config.q0.size(), 0);
  EXPECT_EQ(config.qd0.size(), 0);
  ASSERT_EQ(config.drives.size(), 6u);
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(config.drives[i].kind, DriveConfig::Kind::kPrescribed);
    EXPECT_TRUE(config.drives[i].velocity_source);
    ExpectSeedTrajectory(config.drives[i].trajectory, i);
  }
}

TEST(RunSpecSceneTest, SeedServoTracksTheSeedMotionFromOnTrack) {
  const RunConfig config = LoadScene("seed-servo.json");
  EXPECT_EQ(config.duration, 20.0);
  EXPECT_EQ(config.output_interval, 0.05);
  EXPECT_EQ(config.formulation, Formulation::kJoint);
  EXPECT_EQ(config.method, Method::kBdf);
  EXPECT_EQ(config.rtol, 1e-6);
  EXPECT_EQ(config.gravity, Eigen::Vector3d(0.0, 0.0, -9.81));
  ASSERT_EQ(config.q0.size(), 6);
  ASSERT_EQ(config.qd0.size(), 6);
  ASSERT_EQ(config.drives.size(), 6u);
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(config.q0[i], 0.0);
    EXPECT_EQ(config.qd0[i], kA[i] * kW0) << "joint " << i + 1;
    EXPECT_EQ(config.drives[i].kind, DriveConfig::Kind::kPdServo);
    EXPECT_EQ(config.drives[i].kp, 400.0);
    EXPECT_EQ(config.drives[i].kd, 40.0);
    ExpectSeedTrajectory(config.drives[i].trajectory, i);
  }
}

TEST(RunSpecSceneTest, PassiveSwingReleasesABentPose) {
  const RunConfig config = LoadScene("passive-swing.json");
  EXPECT_EQ(config.duration, 20.0);
  EXPECT_EQ(config.formulation, Formulation::kJoint);
  EXPECT_EQ(config.method, Method::kBdf);
  EXPECT_EQ(config.rtol, 1e-9);
  EXPECT_EQ(config.gravity, Eigen::Vector3d(0.0, 0.0, -9.81));
  Eigen::VectorXd q0(6);
  q0 << 0.0, 0.5, -0.5, 0.0, 0.8, 0.0;
  EXPECT_EQ(config.q0, q0);
  EXPECT_EQ(config.qd0, Eigen::VectorXd::Zero(6));
  ASSERT_EQ(config.drives.size(), 6u);
  for (const DriveConfig& drive : config.drives) {
    EXPECT_EQ(drive.kind, DriveConfig::Kind::kPassive);
  }
}

TEST(RunSpecSceneTest, StiffServoIsShortWithHighGains) {
  const RunConfig config = LoadScene("stiff-servo.json");
  EXPECT_EQ(config.duration, 2.0);
  EXPECT_EQ(config.formulation, Formulation::kJoint);
  EXPECT_EQ(config.method, Method::kBdf);
  EXPECT_EQ(config.rtol, 1e-6);
  ASSERT_EQ(config.drives.size(), 6u);
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(config.drives[i].kind, DriveConfig::Kind::kPdServo);
    EXPECT_EQ(config.drives[i].kp, 1e6);
    EXPECT_EQ(config.drives[i].kd, 2e4);
    EXPECT_EQ(config.qd0[i], kA[i] * kW0);
    ExpectSeedTrajectory(config.drives[i].trajectory, i);
  }
}

TEST(RunSpecDefaultsTest, EmptySpecGivesTheDocumentedDefaults) {
  const RunConfig config = ToRunConfig(ParseRunSpecJson("{}", "empty.json"), kJoints, "e");
  EXPECT_EQ(config.duration, 20.0);
  EXPECT_EQ(config.output_interval, 0.05);
  EXPECT_EQ(config.max_step, 0.0);
  EXPECT_EQ(config.formulation, Formulation::kAuto);
  EXPECT_EQ(config.method, Method::kBdf);
  EXPECT_EQ(config.erk_table, "");
  EXPECT_EQ(config.rtol, 1e-6);
  EXPECT_EQ(config.atol, 1e-8);
  EXPECT_EQ(config.fixed_step, 1e-3);
  EXPECT_EQ(config.gravity, Eigen::Vector3d(0.0, 0.0, -9.81));
  EXPECT_EQ(config.q0.size(), 0);
  EXPECT_EQ(config.qd0.size(), 0);
  EXPECT_TRUE(config.want_torques);
  EXPECT_EQ(config.baumgarte.alpha, 10.0);
  EXPECT_EQ(config.baumgarte.beta, 25.0);
  EXPECT_EQ(config.max_steps, 0);  // the default budget, resolved by the run (run_budget.h)
  EXPECT_EQ(config.max_cpu_s, 0.0);
  ASSERT_EQ(config.drives.size(), 6u);
  for (const DriveConfig& drive : config.drives) {
    EXPECT_EQ(drive.kind, DriveConfig::Kind::kPassive);
  }
}

TEST(RunSpecDefaultsTest, ExplicitZerosAndFalseAreKept) {
  const RunConfig config =
      ToRunConfig(ParseRunSpecJson(R"({"gravity": {}, "want_torques": false, "max_step_s": 0,
                           "baumgarte": {"alpha": 0}})",
                                   "t.json"),
                  kJoints, "t.json");
  EXPECT_EQ(config.gravity, Eigen::Vector3d::Zero());
  EXPECT_FALSE(config.want_torques);
  EXPECT_EQ(config.max_step, 0.0);
  EXPECT_EQ(config.baumgarte.alpha, 0.0);
  EXPECT_EQ(config.baumgarte.beta, 25.0);
}

TEST(RunSpecDrivesTest, MatchJointsByNameOrPosition) {
  const RunConfig config = ToRunConfig(ParseRunSpecJson(R"({"drives": [
      {"joint": "joint5", "torque": {"constant": 2.5}},
      {"pd_servo": {"kp": 7, "kd": 1, "trajectory": {"sum_of_sines": {"offset": 0.3}}}},
      {"joint": "joint1", "prescribed": {"trajectory": {"spline": {
          "times_s": [0, 1, 2], "values": [0, 0.5, 0.25]}}}}]})",
                                                        "t.json"),
                                       kJoints, "t.json");
  ASSERT_EQ(config.drives.size(), 6u);
  EXPECT_EQ(config.drives[4].kind, DriveConfig::Kind::kTorque);
  EXPECT_EQ(config.drives[4].constant, 2.5);
  EXPECT_EQ(config.drives[1].kind, DriveConfig::Kind::kPdServo);  // drives[1], by position
  EXPECT_EQ(config.drives[1].kp, 7.0);
  EXPECT_EQ(config.drives[1].trajectory.offset, 0.3);
  EXPECT_EQ(config.drives[0].kind, DriveConfig::Kind::kPrescribed);
  EXPECT_EQ(config.drives[0].trajectory.kind, Trajectory::Kind::kSpline);
  EXPECT_EQ(config.drives[0].trajectory.times, (std::vector<double>{0, 1, 2}));
  EXPECT_EQ(config.drives[0].trajectory.values, (std::vector<double>{0, 0.5, 0.25}));
  EXPECT_FALSE(config.drives[0].velocity_source);
  for (int i : {2, 3, 5}) EXPECT_EQ(config.drives[i].kind, DriveConfig::Kind::kPassive);
}

TEST(RunSpecJsonTest, AcceptsLowerCamelCaseNames) {
  const v1::RunSpec spec =
      ParseRunSpecJson(R"({"durationS": 3, "outputIntervalS": 0.5, "initialQ": []})", "t.json");
  EXPECT_EQ(spec.duration_s(), 3.0);
  EXPECT_EQ(spec.output_interval_s(), 0.5);
}

TEST(RunSpecJsonTest, UnknownFieldIsNamed) {
  const std::string top = ErrorOf(R"({"duration_s": 1, "durations": 2})");
  EXPECT_THAT(top, HasSubstr("test.json: invalid JSON/RunSpec: "));
  EXPECT_THAT(top, HasSubstr("durations: Cannot find field"));
  EXPECT_THAT(top, HasSubstr("; see models/irb1600/seed-run.json for an example"));
  const std::string nested = ErrorOf(R"({"drives": [{"pd_servo": {"kpp": 1}}]})");
  EXPECT_THAT(nested, HasSubstr("(drives[0].pd_servo) kpp: Cannot find field"));
}

TEST(RunSpecJsonTest, MalformedJsonIsReported) {
  EXPECT_THAT(ErrorOf(R"({"duration_s": )"),
              HasSubstr("test.json: invalid JSON/RunSpec: Unexpected end of string"));
  EXPECT_THAT(ErrorOf(R"({"method": 3})"), HasSubstr("test.json: invalid JSON/RunSpec: "));
  EXPECT_THAT(ErrorOf(R"({"drives": [{"torque": {}, "passive": {}}]})"),
              HasSubstr("oneof field 'kind' is already set"));
}

TEST(RunSpecJsonTest, UnreadableFileIsNamed) {
  const std::string path = ModelFile("no-such-spec.json");
  try {
    LoadRunSpecFile(path);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr(path + ": cannot read the run spec"));
    EXPECT_THAT(error.what(), HasSubstr("check the path"));
  }
  EXPECT_THROW(LoadRunSpecFile(std::string(MBSTREAM_SOURCE_DIR) + "/models"), InputError);
}

TEST(RunSpecJsonTest, FileParseErrorsNameTheFile) {
  // A file that is not JSON: its path leads the message.
  const std::string path = std::string(MBSTREAM_SOURCE_DIR) + "/CMakeLists.txt";
  try {
    LoadRunSpecFile(path);
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr(path + ": invalid JSON/RunSpec: "));
  }
}

TEST(RunSpecJsonTest, PrintsProtoFieldNamesAndDefaults) {
  const std::string json = RunSpecToJson(ToRunSpec(RunConfig{}));
  EXPECT_THAT(json, HasSubstr(R"("duration_s": 20)"));
  // The default budget (0) leaves the budget fields absent.
  EXPECT_THAT(json, Not(HasSubstr("max_internal_steps")));
  EXPECT_THAT(json, Not(HasSubstr("max_cpu_s")));
  EXPECT_THAT(json, HasSubstr(R"("want_torques": true)"));
  EXPECT_THAT(json, HasSubstr(R"("realtime": 0)"));
  EXPECT_THAT(json, HasSubstr(R"("formulation": "auto")"));
}

// Every field of two configs, exactly.
void ExpectSameConfig(const RunConfig& a, const RunConfig& b) {
  EXPECT_EQ(a.duration, b.duration);
  EXPECT_EQ(a.output_interval, b.output_interval);
  EXPECT_EQ(a.max_step, b.max_step);
  EXPECT_EQ(a.formulation, b.formulation);
  EXPECT_EQ(a.method, b.method);
  EXPECT_EQ(a.erk_table, b.erk_table);
  EXPECT_EQ(a.rtol, b.rtol);
  EXPECT_EQ(a.atol, b.atol);
  EXPECT_EQ(a.fixed_step, b.fixed_step);
  EXPECT_EQ(a.gravity, b.gravity);
  EXPECT_EQ(a.q0, b.q0);
  EXPECT_EQ(a.qd0, b.qd0);
  EXPECT_EQ(a.want_torques, b.want_torques);
  EXPECT_EQ(a.baumgarte.alpha, b.baumgarte.alpha);
  EXPECT_EQ(a.baumgarte.beta, b.baumgarte.beta);
  EXPECT_EQ(a.max_steps, b.max_steps);
  EXPECT_EQ(a.max_cpu_s, b.max_cpu_s);
  ASSERT_EQ(a.drives.size(), b.drives.size());
  for (size_t i = 0; i < a.drives.size(); ++i) {
    SCOPED_TRACE("drive " + std::to_string(i));
    const DriveConfig& x = a.drives[i];
    const DriveConfig& y = b.drives[i];
    EXPECT_EQ(x.kind, y.kind);
    EXPECT_EQ(x.velocity_source, y.velocity_source);
    EXPECT_EQ(x.kp, y.kp);
    EXPECT_EQ(x.kd, y.kd);
    EXPECT_EQ(x.constant, y.constant);
    EXPECT_EQ(x.amplitude, y.amplitude);
    EXPECT_EQ(x.omega, y.omega);
    EXPECT_EQ(x.phase, y.phase);
    EXPECT_EQ(x.trajectory.kind, y.trajectory.kind);
    EXPECT_EQ(x.trajectory.offset, y.trajectory.offset);
    EXPECT_EQ(x.trajectory.amplitude, y.trajectory.amplitude);
    EXPECT_EQ(x.trajectory.omega, y.trajectory.omega);
    EXPECT_EQ(x.trajectory.phase, y.trajectory.phase);
    EXPECT_EQ(x.trajectory.times, y.trajectory.times);
    EXPECT_EQ(x.trajectory.values, y.trajectory.values);
  }
}

// A config with no field at its default and awkward doubles (not exact in decimal).
RunConfig EveryFieldSet() {
  RunConfig config;
  config.duration = 7.25;
  config.output_interval = 0.1 / 3.0;
  config.max_step = 1e-3 / 7.0;
  config.formulation = Formulation::kBodyBaumgarte;
  config.method = Method::kErk;
  config.erk_table = "ARKODE_DORMAND_PRINCE_7_4_5";
  config.rtol = 1.0 / 3.0 * 1e-7;
  config.atol = 2.0 / 7.0 * 1e-9;
  config.fixed_step = 1e-4 / 3.0;
  config.gravity = {0.1, -0.2, -9.80665};
  config.q0 = Eigen::VectorXd::LinSpaced(6, -kPi / 7.0, kPi / 3.0);
  config.qd0 = Eigen::VectorXd::LinSpaced(6, 0.1, -std::numbers::e);
  config.want_torques = false;
  config.baumgarte = {12.5 / 3.0, 33.0 / 7.0};
  config.max_steps = 123'457;
  config.max_cpu_s = 12.5 / 3.0;
  config.drives.resize(6);
  DriveConfig& prescribed = config.drives[0];
  prescribed.kind = DriveConfig::Kind::kPrescribed;
  prescribed.velocity_source = true;
  prescribed.trajectory.offset = -0.1 / 3.0;
  prescribed.trajectory.amplitude = {kA[1], 1e-300, -2.0};
  prescribed.trajectory.omega = {kW0, 3.0, 0.0};
  prescribed.trajectory.phase = {0.0, kPi / 2.0, -1.0 / 3.0};
  DriveConfig& torque = config.drives[2];
  torque.kind = DriveConfig::Kind::kTorque;
  torque.constant = -12.0 / 7.0;
  torque.amplitude = 3.5;
  torque.omega = 2.0 * kPi;
  torque.phase = 0.1;
  DriveConfig& servo = config.drives[3];
  servo.kind = DriveConfig::Kind::kPdServo;
  servo.kp = 400.0 / 3.0;
  servo.kd = 0.0;
  servo.trajectory.kind = Trajectory::Kind::kSpline;
  servo.trajectory.times = {0.0, 0.5, 1.0 / 3.0 + 1.0};
  servo.trajectory.values = {0.0, kPi / 9.0, -5e-17};
  config.drives[5].kind = DriveConfig::Kind::kPdServo;  // gains zero, sine with no terms
  config.drives[5].trajectory.offset = 0.7;
  return config;
}

TEST(RunSpecRoundTripTest, ConfigSurvivesSpecAndJson) {
  const RunConfig config = EveryFieldSet();
  const std::string json = RunSpecToJson(ToRunSpec(config));
  const v1::RunSpec parsed = ParseRunSpecJson(json, "round-trip.json");
  const RunConfig back = ToRunConfig(parsed, kJoints, "round-trip.json");
  ExpectSameConfig(config, back);
  EXPECT_EQ(RunSpecToJson(ToRunSpec(back)), json);
}

TEST(RunSpecRoundTripTest, ZeroGravityStaysZero) {
  RunConfig config;
  config.gravity.setZero();
  config.drives.resize(6);
  const RunConfig back = ToRunConfig(ParseRunSpecJson(RunSpecToJson(ToRunSpec(config)), "rt.json"),
                                     kJoints, "rt.json");
  ExpectSameConfig(config, back);
}

TEST(RunSpecRoundTripTest, ShippedScenesSurvive) {
  for (const char* name :
       {"seed-run.json", "seed-servo.json", "passive-swing.json", "stiff-servo.json"}) {
    SCOPED_TRACE(name);
    const RunConfig config = LoadScene(name);
    const RunConfig back =
        ToRunConfig(ParseRunSpecJson(RunSpecToJson(ToRunSpec(config)), name), kJoints, name);
    ExpectSameConfig(config, back);
  }
}

}  // namespace
}  // namespace mbstream

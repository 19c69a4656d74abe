// ToRunConfig's validation: every invalid spec is refused with a message that names the
// file and the field, says what is wrong and what to do.
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "server/spec/run_spec_json.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

const std::vector<std::string> kJoints = {"joint1", "joint2", "joint3",
                                          "joint4", "joint5", "joint6"};

std::string ErrorOf(const std::string& json) {
  try {
    ToRunConfig(ParseRunSpecJson(json, "test.json"), kJoints, "test.json");
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

struct InvalidSpec {
  const char* name;     // the test's name
  std::string json;     // the spec
  std::string message;  // expected in the error: "test.json: <field>: <problem>"
  std::string advice;   // expected in the error too: what to do
};

void PrintTo(const InvalidSpec& spec, std::ostream* os) { *os << spec.name; }

class RunSpecValidationTest : public ::testing::TestWithParam<InvalidSpec> {};

TEST_P(RunSpecValidationTest, IsRefusedWithFieldAndAdvice) {
  const std::string error = ErrorOf(GetParam().json);
  EXPECT_THAT(error, HasSubstr(GetParam().message));
  EXPECT_THAT(error, HasSubstr(GetParam().advice));
}

std::string Drive(const std::string& drive) { return R"({"drives": [)" + drive + "]}"; }

std::string Spline(const std::string& times, const std::string& values) {
  return Drive(R"({"prescribed": {"trajectory": {"spline": {"times_s": )" + times +
               R"(, "values": )" + values + "}}}}");
}

const std::string kJointList = "joint1, joint2, joint3, joint4, joint5, joint6";

INSTANTIATE_TEST_SUITE_P(
    Times, RunSpecValidationTest,
    ::testing::Values(
        InvalidSpec{"ZeroDuration", R"({"duration_s": 0})",
                    "test.json: duration_s: must be > 0 (s), got 0",
                    "give the simulated time span"},
        InvalidSpec{"NegativeDuration", R"({"duration_s": -1})",
                    "test.json: duration_s: must be > 0 (s), got -1",
                    "give the simulated time span"},
        InvalidSpec{"ZeroOutputInterval", R"({"output_interval_s": 0})",
                    "test.json: output_interval_s: must be > 0 (s), got 0",
                    "give the time between output frames"},
        InvalidSpec{"NegativeOutputInterval", R"({"output_interval_s": -0.05})",
                    "test.json: output_interval_s: must be > 0 (s), got -0.05",
                    "give the time between output frames"},
        InvalidSpec{"OutputIntervalLongerThanDuration",
                    R"({"duration_s": 1, "output_interval_s": 2})",
                    "test.json: output_interval_s: 2 s is longer than duration_s (1 s)",
                    "give an interval no longer than the duration"},
        InvalidSpec{"OutputIntervalLongerThanDefaultDuration", R"({"output_interval_s": 30})",
                    "test.json: output_interval_s: 30 s is longer than duration_s (20 s)",
                    "give an interval no longer than the duration"},
        InvalidSpec{"NegativeMaxStep", R"({"max_step_s": -0.1})",
                    "test.json: max_step_s: must be >= 0 (s), got -0.1",
                    "give the largest internal step, or 0 for no limit"},
        InvalidSpec{"ZeroFixedStepForRk4", R"({"method": "rk4", "fixed_step_s": 0})",
                    "test.json: fixed_step_s: must be > 0 (s) for method rk4, got 0",
                    "give the step, e.g. 0.001"},
        InvalidSpec{"NegativeFixedStepForEuler", R"({"method": "euler", "fixed_step_s": -1e-3})",
                    "test.json: fixed_step_s: must be > 0 (s) for method euler, got -0.001",
                    "give the step, e.g. 0.001"}),
    [](const auto& info) { return info.param.name; });

INSTANTIATE_TEST_SUITE_P(
    Solver, RunSpecValidationTest,
    ::testing::Values(
        InvalidSpec{"ZeroRtol", R"({"rtol": 0})", "test.json: rtol: must be in (0, 1), got 0",
                    "give a relative tolerance, e.g. 1e-6"},
        InvalidSpec{"RtolOne", R"({"rtol": 1})", "test.json: rtol: must be in (0, 1), got 1",
                    "give a relative tolerance, e.g. 1e-6"},
        InvalidSpec{"NegativeAtol", R"({"atol": -1e-8})",
                    "test.json: atol: must be in (0, 1), got -1e-08",
                    "give an absolute tolerance, e.g. 1e-8"},
        InvalidSpec{"AtolAboveOne", R"({"atol": 2})", "test.json: atol: must be in (0, 1), got 2",
                    "give an absolute tolerance, e.g. 1e-8"},
        InvalidSpec{"UnknownFormulation", R"({"formulation": "minimal"})",
                    "test.json: formulation: unknown name 'minimal'",
                    "give one of auto, kinematic, joint, body-index3, body-index2, "
                    "body-baumgarte"},
        InvalidSpec{"UnknownMethod", R"({"method": "rk45"})",
                    "test.json: method: unknown name 'rk45'",
                    "give one of bdf, adams, erk, dirk, ida, rk4, euler"},
        InvalidSpec{"ZeroMaxInternalSteps", R"({"max_internal_steps": 0})",
                    "test.json: max_internal_steps: must be > 0, got 0",
                    "give the most internal steps"},
        InvalidSpec{"ZeroMaxCpu", R"({"max_cpu_s": 0})",
                    "test.json: max_cpu_s: must be > 0 (s of CPU), got 0",
                    "give the most CPU seconds the run may use"},
        InvalidSpec{"NegativeBaumgarteBeta", R"({"baumgarte": {"beta": -1}})",
                    "test.json: baumgarte.beta: must be >= 0 (1/s^2), got -1",
                    "give a non-negative feedback gain"},
        InvalidSpec{"NegativeRealtime", R"({"realtime": -1})",
                    "test.json: realtime: must be >= 0 (simulated s per wall-clock s), got -1",
                    "give 0 for as fast as possible or 1 for real time"},
        InvalidSpec{"NegativeMaxOutputFrames", R"({"max_output_frames": -1})",
                    "test.json: max_output_frames: must be >= 0, got -1",
                    "give 0 for the server's limit"}),
    [](const auto& info) { return info.param.name; });

INSTANTIATE_TEST_SUITE_P(
    InitialState, RunSpecValidationTest,
    ::testing::Values(
        InvalidSpec{
            "InitialQTooShort", R"({"initial_q": [0, 0.5, 1]})",
            "test.json: initial_q: has 3 values but the model has 6 joints (" + kJointList + ")",
            "give none or one per joint (rad or m) in the model's joint order"},
        InvalidSpec{"InitialQTooLong", R"({"initial_q": [0, 0, 0, 0, 0, 0, 0]})",
                    "test.json: initial_q: has 7 values but the model has 6 joints",
                    "give none or one per joint (rad or m)"},
        InvalidSpec{"InitialQdWrongSize", R"({"initial_qd": [1, 2]})",
                    "test.json: initial_qd: has 2 values but the model has 6 joints",
                    "give none or one per joint (rad/s or m/s)"}),
    [](const auto& info) { return info.param.name; });

INSTANTIATE_TEST_SUITE_P(
    Drives, RunSpecValidationTest,
    ::testing::Values(
        InvalidSpec{
            "MoreDrivesThanJoints",
            Drive(R"({"passive": {}}, {"passive": {}}, {"passive": {}}, {"passive": {}},
                             {"passive": {}}, {"passive": {}}, {"passive": {}})"),
            "test.json: drives: has 7 drives but the model has 6 joints (" + kJointList + ")",
            "give at most one drive per joint"},
        InvalidSpec{"UnknownJointName",
                    Drive(R"({"passive": {}}, {"joint": "elbow", "passive": {}})"),
                    "test.json: drives[1].joint: the model has no joint named 'elbow'",
                    "give one of " + kJointList},
        InvalidSpec{
            "DuplicateJointName",
            Drive(R"({"joint": "joint2", "passive": {}}, {"joint": "joint2", "torque": {}})"),
            "test.json: drives[1]: joint 'joint2' already has a drive (drives[0])",
            "give each joint at most one drive"},
        InvalidSpec{"NamedDriveForAPositionalOne",
                    Drive(R"({"passive": {}}, {"joint": "joint1", "passive": {}})"),
                    "test.json: drives[1]: joint 'joint1' already has a drive (drives[0])",
                    "give each joint at most one drive"},
        InvalidSpec{"NoDriveKind", Drive(R"({"joint": "joint1"})"),
                    "test.json: drives[0]: no drive kind",
                    "give one of prescribed, torque, pd_servo, external, pose or passive"},
        InvalidSpec{"NoTrajectory", Drive(R"({"prescribed": {"velocity_source": true}})"),
                    "test.json: drives[0].prescribed.trajectory: missing",
                    "give a sum_of_sines or a spline"},
        InvalidSpec{"NegativeKp",
                    Drive(R"({"passive": {}}, {"passive": {}}, {"pd_servo": {"kp": -1, "kd": 1,
                             "trajectory": {"sum_of_sines": {}}}})"),
                    "test.json: drives[2].pd_servo.kp: must be >= 0 (N*m/rad or N/m), got -1",
                    "give a non-negative stiffness gain"},
        InvalidSpec{
            "NegativeKd",
            Drive(R"({"pd_servo": {"kp": 1, "kd": -2, "trajectory": {"sum_of_sines": {}}}})"),
            "test.json: drives[0].pd_servo.kd: must be >= 0 (N*m*s/rad or N*s/m), got -2",
            "give a non-negative damping gain"},
        InvalidSpec{"SplineTimesNotIncreasing", Spline("[0, 1, 1]", "[0, 1, 2]"),
                    "test.json: drives[0].prescribed.trajectory.spline.times_s[2]: 1 s is not "
                    "after times_s[1] (1 s)",
                    "give strictly increasing times"},
        InvalidSpec{"SplineTimesDecreasing", Spline("[0, 2, 1]", "[0, 1, 2]"),
                    "test.json: drives[0].prescribed.trajectory.spline.times_s[2]: 1 s is not "
                    "after times_s[1] (2 s)",
                    "give strictly increasing times"},
        InvalidSpec{"SplineSizesDiffer", Spline("[0, 1, 2]", "[0, 1]"),
                    "test.json: drives[0].prescribed.trajectory.spline: times_s has 3 entries "
                    "but values has 2",
                    "give one value per time"},
        InvalidSpec{"SplineOnePoint", Spline("[0]", "[1]"),
                    "test.json: drives[0].prescribed.trajectory.spline: needs at least 2 "
                    "points, has 1",
                    "give at least 2 (times_s, values) pairs"},
        InvalidSpec{"SplineEmpty", Spline("[]", "[]"),
                    "test.json: drives[0].prescribed.trajectory.spline: needs at least 2 "
                    "points, has 0",
                    "give at least 2 (times_s, values) pairs"}),
    [](const auto& info) { return info.param.name; });

// Protobuf's JSON mapping spells non-finite doubles "NaN", "Infinity" and "-Infinity".
INSTANTIATE_TEST_SUITE_P(
    NonFinite, RunSpecValidationTest,
    ::testing::Values(
        InvalidSpec{"Duration", R"({"duration_s": "NaN"})",
                    "test.json: duration_s: is nan, not a finite number",
                    "give a finite value (s)"},
        InvalidSpec{"OutputInterval", R"({"output_interval_s": "Infinity"})",
                    "test.json: output_interval_s: is inf, not a finite number",
                    "give a finite value (s)"},
        InvalidSpec{"MaxStep", R"({"max_step_s": "Infinity"})",
                    "test.json: max_step_s: is inf, not a finite number",
                    "give a finite value (s)"},
        InvalidSpec{"Rtol", R"({"rtol": "NaN"})", "test.json: rtol: is nan, not a finite number",
                    "give a finite value (dimensionless)"},
        InvalidSpec{"Atol", R"({"atol": "-Infinity"})",
                    "test.json: atol: is -inf, not a finite number",
                    "give a finite value (dimensionless)"},
        InvalidSpec{"FixedStepForBdf", R"({"fixed_step_s": "NaN"})",
                    "test.json: fixed_step_s: is nan, not a finite number",
                    "give a finite value (s)"},
        InvalidSpec{"Gravity", R"({"gravity": {"z": "-Infinity"}})",
                    "test.json: gravity.z: is -inf, not a finite number",
                    "give a finite value (m/s^2)"},
        InvalidSpec{"InitialQ", R"({"initial_q": [0, 0, 0, "NaN", 0, 0]})",
                    "test.json: initial_q[3] (joint4): is nan, not a finite number",
                    "give a finite value (rad or m)"},
        InvalidSpec{"InitialQd", R"({"initial_qd": [0, 0, 0, 0, 0, "Infinity"]})",
                    "test.json: initial_qd[5] (joint6): is inf, not a finite number",
                    "give a finite value (rad/s or m/s)"},
        InvalidSpec{"SineOffset",
                    Drive(R"({"prescribed": {"trajectory": {"sum_of_sines": {"offset": "NaN"}}}})"),
                    "test.json: drives[0].prescribed.trajectory.sum_of_sines.offset: is nan",
                    "give a finite value (rad or m)"},
        InvalidSpec{"SineAmplitude",
                    Drive(R"({"pd_servo": {"trajectory": {"sum_of_sines": {"terms": [
                             {"amplitude": 1}, {"amplitude": "-Infinity"}]}}}})"),
                    "test.json: drives[0].pd_servo.trajectory.sum_of_sines.terms[1].amplitude: "
                    "is -inf",
                    "give a finite value (rad or m)"},
        InvalidSpec{"SineOmega", Drive(R"({"prescribed": {"trajectory": {"sum_of_sines": {"terms": [
                             {"omega": "NaN"}]}}}})"),
                    "test.json: drives[0].prescribed.trajectory.sum_of_sines.terms[0].omega: "
                    "is nan",
                    "give a finite value (rad/s)"},
        InvalidSpec{"SinePhase", Drive(R"({"prescribed": {"trajectory": {"sum_of_sines": {"terms": [
                             {"phase": "NaN"}]}}}})"),
                    "test.json: drives[0].prescribed.trajectory.sum_of_sines.terms[0].phase: "
                    "is nan",
                    "give a finite value (rad)"},
        InvalidSpec{"SplineTime", Spline(R"([0, "NaN"])", "[0, 1]"),
                    "test.json: drives[0].prescribed.trajectory.spline.times_s[1]: is nan",
                    "give a finite value (s)"},
        InvalidSpec{"SplineValue", Spline("[0, 1]", R"([0, "Infinity"])"),
                    "test.json: drives[0].prescribed.trajectory.spline.values[1]: is inf",
                    "give a finite value (rad or m)"},
        InvalidSpec{"TorqueConstant", Drive(R"({"torque": {"constant": "NaN"}})"),
                    "test.json: drives[0].torque.constant: is nan, not a finite number",
                    "give a finite value (N*m or N)"},
        InvalidSpec{"TorqueAmplitude", Drive(R"({"torque": {"amplitude": "Infinity"}})"),
                    "test.json: drives[0].torque.amplitude: is inf", "give a finite value"},
        InvalidSpec{"TorqueOmega", Drive(R"({"torque": {"omega": "NaN"}})"),
                    "test.json: drives[0].torque.omega: is nan", "give a finite value (rad/s)"},
        InvalidSpec{"TorquePhase", Drive(R"({"torque": {"phase": "NaN"}})"),
                    "test.json: drives[0].torque.phase: is nan", "give a finite value (rad)"},
        InvalidSpec{"Kp", Drive(R"({"pd_servo": {"kp": "NaN"}})"),
                    "test.json: drives[0].pd_servo.kp: is nan", "give a finite value"},
        InvalidSpec{"BaumgarteAlpha", R"({"baumgarte": {"alpha": "NaN"}})",
                    "test.json: baumgarte.alpha: is nan", "give a finite value (1/s)"},
        InvalidSpec{"Realtime", R"({"realtime": "Infinity"})",
                    "test.json: realtime: is inf, not a finite number", "give a finite value"}),
    [](const auto& info) { return info.param.name; });

TEST(RunSpecValidationEdgeTest, FixedStepIsOnlyRequiredForFixedStepMethods) {
  EXPECT_EQ(ErrorOf(R"({"method": "bdf", "fixed_step_s": 0})"), "");
  EXPECT_EQ(ErrorOf(R"({"method": "rk4", "fixed_step_s": 0.01})"), "");
  EXPECT_EQ(ErrorOf(R"({"method": "euler"})"), "");  // the default step, 1e-3 s
}

TEST(RunSpecValidationEdgeTest, BoundaryValuesAreAccepted) {
  EXPECT_EQ(ErrorOf(R"({"duration_s": 1, "output_interval_s": 1})"), "");
  EXPECT_EQ(ErrorOf(R"({"max_step_s": 0, "realtime": 0, "max_output_frames": 0})"), "");
  EXPECT_EQ(ErrorOf(R"({"initial_q": [], "initial_qd": [1, 2, 3, 4, 5, 6]})"), "");
  EXPECT_EQ(ErrorOf(Drive(R"({"pd_servo": {"kp": 0, "kd": 0, "trajectory": {"spline": {
                               "times_s": [0, 1e-9], "values": [0, 0]}}}})")),
            "");
  EXPECT_EQ(ErrorOf(R"({"formulation": "", "method": ""})"), "");  // auto, bdf
}

TEST(RunSpecValidationEdgeTest, MessagesNameTheSource) {
  try {
    ToRunConfig(ParseRunSpecJson(R"({"duration_s": 0})", "x"), kJoints, "scenes/mine.json");
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("scenes/mine.json: duration_s: "));
  }
}

// A model with a free joint: initial_q takes its 7 position coordinates, initial_qd its 6
// velocities; the messages count and name coordinates, not joints.
TEST(RunSpecValidationEdgeTest, FreeJointsTakePositionsAndVelocitiesApart) {
  const SpecCoordinates box{
      {"arm", "box.x", "box.y", "box.z", "box.qw", "box.qx", "box.qy", "box.qz"},
      {"arm", "box.vx", "box.vy", "box.vz", "box.wx", "box.wy", "box.wz"}};
  const RunConfig config = ToRunConfig(ParseRunSpecJson(R"({"initial_q": [0.1, 1, 2, 3, 1, 0, 0, 0],
                           "initial_qd": [0, 0, 0, -1, 0, 0, 2]})",
                                                        "free.json"),
                                       box, "free.json");
  ASSERT_EQ(config.q0.size(), 8);
  ASSERT_EQ(config.qd0.size(), 7);
  EXPECT_EQ(config.q0[3], 3.0);
  EXPECT_EQ(config.qd0[6], 2.0);
  EXPECT_EQ(config.drives.size(), 7u);
  const auto refusal = [&](const std::string& json) {
    try {
      ToRunConfig(ParseRunSpecJson(json, "free.json"), box, "free.json");
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  EXPECT_THAT(refusal(R"({"initial_q": [0, 0, 0, 0, 1, 0, 0]})"),
              AllOf(HasSubstr("free.json: initial_q: has 7 values but the model has 8 position "
                              "coordinates (arm, box.x"),
                    HasSubstr("x y z qw qx qy qz")));
  EXPECT_THAT(refusal(R"({"initial_qd": [0, 0, 0, 0, 0, 0, 0, 0]})"),
              HasSubstr("initial_qd: has 8 values but the model has 7 velocity coordinates"));
  EXPECT_THAT(refusal(R"({"initial_q": [0, 0, 0, 0, "NaN", 0, 0, 0]})"),
              HasSubstr("initial_q[4] (box.qw): is nan"));
}

INSTANTIATE_TEST_SUITE_P(
    Target, RunSpecValidationTest,
    ::testing::Values(
        InvalidSpec{"NegativeTcpTarget", R"({"target": {"tcp_error_m": -1e-5}})",
                    "test.json: target.tcp_error_m: must be > 0 (m), got -1e-05",
                    "give the largest error the run may have"},
        InvalidSpec{"ZeroJointTarget", R"({"target": {"joint_error_rad": 0}})",
                    "test.json: target.joint_error_rad: must be > 0 (rad), got 0",
                    "give the largest error the run may have"},
        InvalidSpec{"InfiniteEnergyTarget", R"({"target": {"energy_error_rel": "Infinity"}})",
                    "test.json: target.energy_error_rel: is inf, not a finite number",
                    "give a finite value"},
        InvalidSpec{"EmptyTarget", R"({"target": {}})", "test.json: target: is empty",
                    "give tcp_error_m, joint_error_rad or energy_error_rel"},
        InvalidSpec{"AutoWithoutTarget", R"({"method": "auto"})",
                    "test.json: method: auto chooses the method for an accuracy target",
                    "give target.tcp_error_m"}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(RunSpecTargetTest, TargetWithoutMethodIsAuto) {
  const RunConfig config = ToRunConfig(
      ParseRunSpecJson(R"({"target": {"tcp_error_m": 1e-5}, "verify": false})", "t.json"), kJoints,
      "t.json");
  EXPECT_TRUE(config.method_auto);
  EXPECT_DOUBLE_EQ(config.target.tcp_error_m, 1e-5);
  EXPECT_FALSE(config.verify);
  // And back: the recorded spec keeps the target and "auto".
  const v1::RunSpec spec = ToRunSpec(config);
  EXPECT_EQ(spec.method(), "auto");
  EXPECT_DOUBLE_EQ(spec.target().tcp_error_m(), 1e-5);
  EXPECT_FALSE(spec.target().has_joint_error_rad());
}

}  // namespace
}  // namespace mbstream

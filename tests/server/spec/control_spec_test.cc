// The spec's sampled drives: external drives and pd_servo.period_s, control_timeout_s.
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "server/spec/run_spec_json.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

using ::testing::HasSubstr;

const std::vector<std::string> kJoints = {"joint1", "joint2", "joint3",
                                          "joint4", "joint5", "joint6"};

RunConfig Parse(const std::string& json) {
  return ToRunConfig(ParseRunSpecJson(json, "c.json"), kJoints, "c.json");
}

std::string ErrorOf(const std::string& json) {
  try {
    Parse(json);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(ControlSpecTest, ExternalDrivesAndSampledServo) {
  const RunConfig config = Parse(R"({"drives": [
      {"joint": "joint1", "external": {"command": "effort", "period_s": 0.001}},
      {"joint": "joint2", "external": {"command": "position", "period_s": 0.001, "kp": 400, "kd": 40}},
      {"joint": "joint3", "external": {"command": "velocity", "period_s": 0.001, "kd": 40}},
      {"joint": "joint4", "external": {"period_s": 0.001}},
      {"joint": "joint5", "pd_servo": {"kp": 1, "kd": 2, "period_s": 0.001,
                                       "trajectory": {"sum_of_sines": {"offset": 0.1}}}}],
      "control_timeout_s": 2.5, "hold_last_command": true})");
  ASSERT_EQ(config.drives.size(), 6u);
  EXPECT_EQ(config.drives[0].kind, DriveConfig::Kind::kExternal);
  EXPECT_EQ(config.drives[0].command, DriveConfig::Command::kEffort);
  EXPECT_EQ(config.drives[0].period, 0.001);
  EXPECT_EQ(config.drives[1].command, DriveConfig::Command::kPosition);
  EXPECT_EQ(config.drives[1].kp, 400.0);
  EXPECT_EQ(config.drives[1].kd, 40.0);
  EXPECT_EQ(config.drives[2].command, DriveConfig::Command::kVelocity);
  EXPECT_EQ(config.drives[3].command, DriveConfig::Command::kEffort);  // the default
  EXPECT_EQ(config.drives[4].kind, DriveConfig::Kind::kPdServo);
  EXPECT_EQ(config.drives[4].period, 0.001);
  EXPECT_EQ(config.drives[5].kind, DriveConfig::Kind::kPassive);
  // And back, through the recorded spec.
  const RunConfig back =
      ToRunConfig(ParseRunSpecJson(RunSpecToJson(ToRunSpec(config)), "b.json"), kJoints, "b.json");
  EXPECT_EQ(back.drives, config.drives);
}

TEST(ControlSpecTest, BadFieldsAreNamed) {
  EXPECT_THAT(ErrorOf(R"({"drives": [{"external": {"command": "torque", "period_s": 0.01}}]})"),
              HasSubstr("c.json: drives[0].external.command: is 'torque'; give effort, "
                        "position or velocity"));
  EXPECT_THAT(ErrorOf(R"({"drives": [{"external": {"command": "effort"}}]})"),
              HasSubstr("drives[0].external.period_s: must be > 0 (s), got 0"));
  EXPECT_THAT(ErrorOf(R"({"drives": [{"external": {"period_s": "NaN"}}]})"),
              HasSubstr("drives[0].external.period_s: is nan, not a finite number"));
  EXPECT_THAT(ErrorOf(R"({"drives": [{"external": {"period_s": 1e-9}}]})"),
              HasSubstr("drives[0].external.period_s: is 1e-09 s, below 1e-06 s"));
  EXPECT_THAT(
      ErrorOf(R"({"drives": [{"external": {"command": "velocity", "period_s": 0.01, "kp": 3}}]})"),
      HasSubstr("drives[0].external.kp: is 3 but command velocity has no position error"));
  EXPECT_THAT(ErrorOf(R"({"drives": [{"external": {"period_s": 0.01, "kd": 3}}]})"),
              HasSubstr("drives[0].external.kd: is 3 but command effort applies the command"));
  EXPECT_THAT(ErrorOf(R"({"drives": [{"external": {"command": "position", "period_s": 0.01,
                                                    "kp": -1}}]})"),
              HasSubstr("drives[0].external.kp: must be >= 0"));
  EXPECT_THAT(ErrorOf(R"({"drives": [{"pd_servo": {"kp": 1, "period_s": -1,
                          "trajectory": {"sum_of_sines": {}}}}]})"),
              HasSubstr("drives[0].pd_servo.period_s: must be >= 0 (s), got -1"));
  EXPECT_THAT(ErrorOf(R"({"drives": [{"external": {"period_s": 0.01}},
                                     {"external": {"period_s": 0.02}}]})"),
              HasSubstr("drives[1].external.period_s: is 0.02 s but drives[0].external.period_s "
                        "is 0.01 s; give every sampled drive of a run the same control period"));
  EXPECT_THAT(ErrorOf(R"({"control_timeout_s": 0})"),
              HasSubstr("c.json: control_timeout_s: must be > 0 (s), got 0"));
  EXPECT_THAT(ErrorOf(R"({"control_timeout_s": 1e9})"),
              HasSubstr("control_timeout_s: is 1e+09 s, more than 86400 s"));
}

}  // namespace
}  // namespace mbstream

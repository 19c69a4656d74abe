// RunSpec.initial_bodies at the edge: free bodies by name, each part validated with the field's
// path, an rpy turned into its quaternion, and the recorded spec (ToRunSpec) reading back to
// the same run.
#include <cmath>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "server/spec/initial_bodies_spec.h"
#include "server/spec/run_spec_json.h"
#include "server/spec/spec_override.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

// An arm joint, then two free bodies of a world, then a ball joint.
const SpecCoordinates kBodiesWorld{
    {"arm", "box_a::link.x", "box_a::link.y", "box_a::link.z", "box_a::link.qw", "box_a::link.qx",
     "box_a::link.qy", "box_a::link.qz", "box_b::link.x", "box_b::link.y", "box_b::link.z",
     "box_b::link.qw", "box_b::link.qx", "box_b::link.qy", "box_b::link.qz", "ball.qw", "ball.qx",
     "ball.qy", "ball.qz"},
    {"arm", "box_a::link.vx", "box_a::link.vy", "box_a::link.vz", "box_a::link.wx",
     "box_a::link.wy", "box_a::link.wz", "box_b::link.vx", "box_b::link.vy", "box_b::link.vz",
     "box_b::link.wx", "box_b::link.wy", "box_b::link.wz", "ball.wx", "ball.wy", "ball.wz"}};

RunConfig ConvertBodies(const std::string& json) {
  return ToRunConfig(ParseRunSpecJson(json, "bodies.json"), kBodiesWorld, "bodies.json");
}

std::string BodiesRefusal(const std::string& json) {
  try {
    ConvertBodies(json);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

std::string BodiesSpec(const std::string& entries) {
  return R"({"initial_bodies": [)" + entries + "]}";
}

TEST(InitialBodiesSpecTest, FreeBodiesAreTheSevenCoordinateRuns) {
  EXPECT_EQ(FreeBodyNames(kBodiesWorld.positions),
            (std::vector<std::string>{"box_a::link", "box_b::link"}));
  // A ball joint's four and lone joints named like coordinates are no free body.
  EXPECT_TRUE(FreeBodyNames({"a.x", "a.y", "a.z", "a.qw", "a.qx", "a.qy"}).empty());
  EXPECT_TRUE(FreeBodyNames(kBodiesWorld.velocities).empty());
}

TEST(InitialBodiesSpecTest, EachPartGivenIsKeptAndEachLeftOutStaysAbsent) {
  const RunConfig config = ConvertBodies(BodiesSpec(R"(
      {"name": "box_b::link", "positionM": {"x": 0.5, "y": -0.25, "z": 2},
       "quaternion": {"w": 0.6, "x": 0.8}, "angular_velocity_rad_per_s": {"z": 3}},
      {"name": "box_a::link", "linearVelocityMPerS": {"x": 1, "z": 4}})"));
  ASSERT_EQ(config.initial_bodies.size(), 2u);
  const InitialBodyState& b = config.initial_bodies[0];
  EXPECT_EQ(b.name, "box_b::link");
  ASSERT_TRUE(b.position && b.quaternion && b.angular_velocity);
  EXPECT_EQ(*b.position, Eigen::Vector3d(0.5, -0.25, 2.0));
  EXPECT_EQ(*b.quaternion, Eigen::Vector4d(0.6, 0.8, 0.0, 0.0));
  EXPECT_EQ(*b.angular_velocity, Eigen::Vector3d(0.0, 0.0, 3.0));
  EXPECT_FALSE(b.linear_velocity);
  const InitialBodyState& a = config.initial_bodies[1];
  EXPECT_FALSE(a.position || a.quaternion || a.angular_velocity);
  ASSERT_TRUE(a.linear_velocity);
  EXPECT_EQ(*a.linear_velocity, Eigen::Vector3d(1.0, 0.0, 4.0));
  EXPECT_EQ(config.q0.size(), 0);  // initial_q stays absent: the model's poses under them
}

TEST(InitialBodiesSpecTest, RpyIsTheQuaternionOfRzRyRx) {
  const double roll = 0.3, pitch = -0.7, yaw = 2.1;
  const RunConfig config = ConvertBodies(BodiesSpec(R"({"name": "box_a::link", "rpy": {"roll": 0.3,
      "pitch": -0.7, "yaw": 2.1}})"));
  ASSERT_TRUE(config.initial_bodies.at(0).quaternion);
  const Eigen::Vector4d& q = *config.initial_bodies[0].quaternion;
  const Eigen::Matrix3d expected = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix();
  const Eigen::Matrix3d R = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
  EXPECT_LT((R - expected).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT(std::abs(q.norm() - 1.0), 1e-15);
}

TEST(InitialBodiesSpecTest, TheRecordedSpecReadsBackToTheSameRun) {
  const RunConfig config = ConvertBodies(R"({"initial_q": [0.1, 0, 0, 1, 1, 0, 0, 0, 0, 0, 1, 1, 0,
      0, 0, 1, 0, 0, 0], "initial_bodies": [
      {"name": "box_b::link", "rpy": {"yaw": 1.25}, "linearVelocityMPerS": {"y": -2}},
      {"name": "box_a::link", "positionM": {"x": 3}}]})");
  const v1::RunSpec recorded = ToRunSpec(config);
  ASSERT_EQ(recorded.initial_bodies_size(), 2);
  EXPECT_TRUE(recorded.initial_bodies(0).has_quaternion());  // the rpy as its quaternion
  EXPECT_FALSE(recorded.initial_bodies(0).has_position_m());
  EXPECT_FALSE(recorded.initial_bodies(1).has_quaternion());
  const RunConfig again = ToRunConfig(ParseRunSpecJson(RunSpecToJson(recorded), "recorded.json"),
                                      kBodiesWorld, "recorded");
  EXPECT_EQ(again.initial_bodies, config.initial_bodies);
  EXPECT_TRUE(again == config);
}

TEST(InitialBodiesSpecTest, AnUnknownNameIsRefusedWithTheFreeBodiesListed) {
  EXPECT_THAT(BodiesRefusal(BodiesSpec(R"({"name": "box_a::lnk", "positionM": {"z": 1}})")),
              AllOf(HasSubstr("bodies.json: initial_bodies[0].name: 'box_a::lnk' is no free "
                              "body of the model; did you mean 'box_a::link'?"),
                    HasSubstr("give one of box_a::link, box_b::link")));
  EXPECT_THAT(BodiesRefusal(BodiesSpec(R"({"name": "arm"})")),
              HasSubstr("initial_bodies[0].name: 'arm' is no free body"));
  EXPECT_THAT(BodiesRefusal(BodiesSpec(R"({"name": "ball"})")),
              HasSubstr("initial_bodies[0].name: 'ball' is no free body"));
  EXPECT_THAT(BodiesRefusal(BodiesSpec(R"({"positionM": {"z": 1}})")),
              HasSubstr("initial_bodies[0].name: give a free body's name"));
  try {
    ToRunConfig(ParseRunSpecJson(BodiesSpec(R"({"name": "box"})"), "arm.json"),
                std::vector<std::string>{"joint1", "joint2"}, "arm.json");
    FAIL() << "expected InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("arm.json: initial_bodies[0].name: 'box': the model has "
                                        "no free bodies"));
  }
}

TEST(InitialBodiesSpecTest, ABodyGivenTwiceIsRefused) {
  EXPECT_THAT(BodiesRefusal(BodiesSpec(R"({"name": "box_b::link"}, {"name": "box_a::link"},
                                {"name": "box_b::link", "positionM": {"z": 1}})")),
              HasSubstr("initial_bodies[2].name: 'box_b::link' is given already by "
                        "initial_bodies[0]; give each body once"));
}

TEST(InitialBodiesSpecTest, AQuaternionNotUnitIsRefusedWithItsNorm) {
  EXPECT_THAT(
      BodiesRefusal(BodiesSpec(R"({"name": "box_a::link", "quaternion": {"w": 1, "z": 0.5}})")),
      AllOf(HasSubstr("initial_bodies[0].quaternion: (w x y z) = (1, 0, 0, 0.5) has "
                      "norm 1.11803399"),
            HasSubstr("give a unit quaternion (norm 1 within 1e-6)")));
  EXPECT_THAT(BodiesRefusal(BodiesSpec(R"({"name": "box_a::link", "quaternion": {}})")),
              HasSubstr("has norm 0;"));
  EXPECT_THAT(BodiesRefusal(BodiesSpec(R"({"name": "box_a::link", "quaternion": {"w": -3}})")),
              HasSubstr("initial_bodies[0].quaternion: (w x y z) = (-3, 0, 0, 0) has norm 3;"));
  // Within 1e-6 of unit: accepted as given (the run normalises it).
  const RunConfig near =
      ConvertBodies(BodiesSpec(R"({"name": "box_a::link", "quaternion": {"w": 1.0000009}})"));
  EXPECT_EQ((*near.initial_bodies.at(0).quaternion)[0], 1.0000009);
}

TEST(InitialBodiesSpecTest, NonFiniteValuesAreRefusedWithTheFieldPath) {
  EXPECT_THAT(BodiesRefusal(BodiesSpec(R"({"name": "box_a::link"}, {"name": "box_b::link",
                                 "positionM": {"x": 0, "z": "NaN"}})")),
              HasSubstr("bodies.json: initial_bodies[1].position_m.z: is nan, not a finite "
                        "number; give a finite value (m)"));
  EXPECT_THAT(
      BodiesRefusal(BodiesSpec(R"({"name": "box_a::link", "quaternion": {"w": "Infinity"}})")),
      HasSubstr("initial_bodies[0].quaternion.w: is inf, not a finite number"));
  EXPECT_THAT(
      BodiesRefusal(BodiesSpec(R"({"name": "box_a::link", "rpy": {"pitch": "-Infinity"}})")),
      HasSubstr("initial_bodies[0].rpy.pitch: is -inf, not a finite number; give a "
                "finite value (rad)"));
  EXPECT_THAT(BodiesRefusal(BodiesSpec(R"({"name": "box_a::link",
                                 "linearVelocityMPerS": {"y": "NaN"}})")),
              HasSubstr("initial_bodies[0].linear_velocity_m_per_s.y: is nan"));
  EXPECT_THAT(BodiesRefusal(BodiesSpec(R"({"name": "box_a::link",
                                 "angularVelocityRadPerS": {"x": 1e300}})")),
              HasSubstr("initial_bodies[0].angular_velocity_rad_per_s.x: is 1e+300 rad/s, "
                        "beyond +-1e+06 rad/s"));
}

// A sweep's path reaches an entry by the body's name (spec_override.h): one point per height.
TEST(InitialBodiesSpecTest, ASweepPathSetsOneBodysPartByItsName) {
  v1::RunSpec spec = ParseRunSpecJson(
      BodiesSpec(
          R"({"name": "box_a::link"}, {"name": "box_b::link", "positionM": {"x": 1, "z": 2}})"),
      "base.json");
  ApplySpecOverride("initial_bodies[name=box_b::link].position_m.z", "0.5", &spec, "sweep");
  const RunConfig config = ToRunConfig(spec, kBodiesWorld, "sweep");
  ASSERT_TRUE(config.initial_bodies.at(1).position);
  EXPECT_EQ(*config.initial_bodies[1].position, Eigen::Vector3d(1.0, 0.0, 0.5));
  EXPECT_FALSE(config.initial_bodies[0].position);
}

}  // namespace
}  // namespace mbstream

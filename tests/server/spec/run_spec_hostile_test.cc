// Hostile run specs (issue 36): each is refused at the edge with the field and what to do,
// never read as zeros, cut short, echoed whole or passed on to SUNDIALS.
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "server/spec/json_shape.h"
#include "server/spec/run_spec_json.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Not;

const std::vector<std::string> kJoints = {"joint1", "joint2"};

std::string ErrorOf(const std::string& json) {
  try {
    ToRunConfig(ParseRunSpecJson(json, "hostile.json"), kJoints, "hostile.json");
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(RunSpecHostileTest, NullInAListIsRefusedNotReadAsZero) {
  EXPECT_THAT(ErrorOf(R"({"initial_q": [0.5, null]})"),
              AllOf(HasSubstr("hostile.json: initial_q[1] is null"), HasSubstr("give a number")));
}

TEST(RunSpecHostileTest, ListInsideAListIsRefused) {
  EXPECT_THAT(ErrorOf(R"({"initial_q": [[1, 2], [3]]})"),
              AllOf(HasSubstr("initial_q[0] is a list inside a list"), HasSubstr("flat list")));
  EXPECT_THAT(ErrorOf(R"({"drives": [{"joint": "joint1"}, {"prescribed": {"trajectory":
                  {"spline": {"times_s": [0, [1]]}}}}]})"),
              HasSubstr("drives[1].prescribed.trajectory.spline.times_s[1] is a list"));
}

TEST(RunSpecHostileTest, NulInsideAStringIsRefusedWhole) {
  EXPECT_THAT(ErrorOf(R"({"method": "bdf\u0000rk4"})"),
              AllOf(HasSubstr("method holds a NUL character"), HasSubstr("remove it")));
}

TEST(RunSpecHostileTest, AHugeUnknownKeyIsCutInTheMessage) {
  const std::string key(10 << 20, 'k');
  const std::string error = ErrorOf("{\"" + key + "\": 1}");
  EXPECT_THAT(error, HasSubstr("has a key of 10485760 bytes"));
  EXPECT_LT(error.size(), 400u);
  // Below the key limit the name reaches protobuf, whose message is cut too.
  const std::string unknown = ErrorOf("{\"" + std::string(150, 'u') + "\": 1}");
  EXPECT_THAT(unknown, HasSubstr("invalid JSON/RunSpec"));
  EXPECT_LT(unknown.size(), 700u);
}

TEST(RunSpecHostileTest, BytesThatAreNotUtf8AreRefusedWithTheLine) {
  EXPECT_THAT(
      ErrorOf("{\n\"drives\": [{\"joint\": \"j\xFF\"}]}"),
      AllOf(HasSubstr("hostile.json: line 2: byte 0xFF is not UTF-8"), HasSubstr("convert")));
}

TEST(RunSpecHostileTest, DeepNestingIsRefusedBeforeAnyRecursion) {
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  EXPECT_THAT(ErrorOf("{\"initial_q\": " + deep + "}"), HasSubstr("initial_q[0] is a list"));
  std::string objects;
  for (int i = 0; i < 50000; ++i) objects += "{\"a\":";
  EXPECT_THAT(ErrorOf(objects + "1" + std::string(50000, '}')), HasSubstr("nested more than 32"));
}

TEST(RunSpecHostileTest, ControlCharactersInNamesAreRefused) {
  EXPECT_THAT(ErrorOf(R"({"drives": [{"joint": "joint1\u0001"}]})"),
              HasSubstr("drives[0].joint: holds a control character"));
}

TEST(RunSpecHostileTest, StepsBelowTheSmallestAreRefused) {
  EXPECT_THAT(ErrorOf(R"({"max_step_s": 5e-324})"),
              AllOf(HasSubstr("max_step_s: is 5e-324 s, below the smallest"),
                    HasSubstr("give 0 for no limit")));
  EXPECT_THAT(ErrorOf(R"({"method": "rk4", "fixed_step_s": 1e-300})"),
              HasSubstr("fixed_step_s: is 1e-300 s, below the smallest"));
  EXPECT_EQ(ErrorOf(R"({"max_step_s": 0})"), "");
  EXPECT_EQ(ErrorOf(R"({"max_step_s": 1e-6})"), "");
}

TEST(RunSpecHostileTest, AbsurdGravityIsRefused) {
  EXPECT_THAT(ErrorOf(R"({"gravity": {"z": 1e300}})"),
              AllOf(HasSubstr("gravity.z: is 1e+300 m/s^2"), HasSubstr("z = -9.81")));
  EXPECT_EQ(ErrorOf(R"({"gravity": {"z": -274}})"), "");  // the Sun's surface is fine
}

TEST(RunSpecHostileTest, RetriesOutsideTheirRangeAreRefused) {
  EXPECT_THAT(ErrorOf(R"({"retries": 101})"), HasSubstr("retries: is 101; give 0"));
  EXPECT_THAT(ErrorOf(R"({"retries": -1})"), HasSubstr("retries: is -1"));
  EXPECT_EQ(ErrorOf(R"({"retries": 100})"), "");
}

TEST(RunSpecHostileTest, ValidSpecsPassTheShapeCheck) {
  EXPECT_NO_THROW(CheckJsonShape(R"({"initial_q": [1, 2], "drives": [{"joint": "j"}]})", "x"));
  EXPECT_NO_THROW(CheckJsonShape("not json at all", "x"));  // protobuf reports that
  EXPECT_THAT(ErrorOf("not json"),
              AllOf(HasSubstr("invalid JSON/RunSpec"), Not(HasSubstr("is null"))));
}

TEST(RunSpecHostileTest, CutForMessageKeepsUtf8Whole) {
  EXPECT_EQ(CutForMessage("abc", 5), "abc");
  EXPECT_EQ(CutForMessage("abcdef", 3), "abc...");
  EXPECT_EQ(CutForMessage("a\xC3\xA9z", 2), "a...");  // never half of é
}

}  // namespace
}  // namespace mbstream

// A sweep's overrides: run spec fields by JSON path, grids in order, errors that name the
// point and the path.
#include "server/spec/spec_override.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "server/spec/run_spec_json.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

using ::testing::HasSubstr;

v1::RunSpec Servo() { return LoadRunSpecFile("models/irb1600/seed-servo.json"); }

std::string ErrorOf(const std::string& path, const std::string& value) {
  v1::RunSpec spec = Servo();
  try {
    ApplySpecOverride(path, value, &spec, "sweep");
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(SpecOverrideTest, FieldsListElementsAndDrivesAreSetByPath) {
  v1::RunSpec spec = Servo();
  ApplySpecOverride("rtol", "1e-9", &spec, "sweep");
  ApplySpecOverride("outputIntervalS", "0.1", &spec, "sweep");  // lowerCamelCase too
  ApplySpecOverride("drives[1].pd_servo.kp", "1234.5", &spec, "sweep");
  ApplySpecOverride("initial_q[2]", "0.25", &spec, "sweep");
  ApplySpecOverride("target.tcp_error_m", "1e-5", &spec, "sweep");  // created: absent before
  ApplySpecOverride("method", "adams", &spec, "sweep");             // a bare word: a string
  ApplySpecOverride("keep", "\"every:3\"", &spec, "sweep");
  EXPECT_EQ(spec.rtol(), 1e-9);
  EXPECT_EQ(spec.output_interval_s(), 0.1);
  EXPECT_EQ(spec.drives(1).pd_servo().kp(), 1234.5);
  EXPECT_EQ(spec.drives(0).pd_servo().kp(), Servo().drives(0).pd_servo().kp());
  EXPECT_EQ(spec.drives(1).pd_servo().kd(), Servo().drives(1).pd_servo().kd());
  EXPECT_EQ(spec.initial_q(2), 0.25);
  EXPECT_EQ(spec.target().tcp_error_m(), 1e-5);
  EXPECT_EQ(spec.method(), "adams");
  EXPECT_EQ(spec.keep(), "every:3");

  v1::RunSpec named;
  named.add_drives()->set_joint("joint2");
  named.add_drives()->set_joint("joint5");
  ApplySpecOverride("drives[joint=joint5].pd_servo.kd", "7", &named, "sweep");
  EXPECT_EQ(named.drives(1).pd_servo().kd(), 7.0);
  EXPECT_FALSE(named.drives(0).has_pd_servo());
}

TEST(SpecOverrideTest, ErrorsNameThePathAndWhatToDo) {
  EXPECT_THAT(ErrorOf("rtoll", "1"), HasSubstr("rtoll"));
  EXPECT_THAT(ErrorOf("drives[9].pd_servo.kp", "1"),
              HasSubstr("sweep: drives[9].pd_servo.kp: drives[9]: the base spec's drives has 6 "
                        "elements"));
  EXPECT_THAT(ErrorOf("drives[joint=joint2].pd_servo.kp", "1"),
              HasSubstr("no element of the base spec's drives has joint = joint2"));
  EXPECT_THAT(ErrorOf("drives[x].kp", "1"), HasSubstr("[x] is not a list index"));
  EXPECT_THAT(ErrorOf("rtol.x", "1"), HasSubstr("rtol is a value, not a message"));
  EXPECT_THAT(ErrorOf("drives", "1"), HasSubstr("drives is a list; name an element"));
  EXPECT_THAT(ErrorOf("gravity", "1"), HasSubstr("name one of its fields"));
  v1::RunSpec prescribed = LoadRunSpecFile("models/irb1600/seed-run.json");
  try {
    ApplySpecOverride("drives[0].pd_servo.kp", "1", &prescribed, "sweep");
    ADD_FAILURE() << "a prescribed drive was turned into a servo";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("the base spec gives prescribed there, not pd_servo"));
  }
  EXPECT_THAT(ErrorOf("drives[0", "1"), HasSubstr("'[' is not closed"));
  EXPECT_THAT(ErrorOf("", "1"), HasSubstr("a field name is missing"));
  EXPECT_THAT(ErrorOf("rtol", "\"fast\""), HasSubstr("rtol"));  // a string for a number
}

TEST(SpecOverrideTest, AGridVariesItsLastAxisFastestAndIsBounded) {
  const SweepPoints grid = GridPoints({"a", "b"}, {{"1", "2"}, {"x", "y", "z"}}, 100, "grid");
  ASSERT_EQ(grid.points.size(), 6u);
  EXPECT_EQ(grid.points[0], (std::vector<std::string>{"1", "x"}));
  EXPECT_EQ(grid.points[1], (std::vector<std::string>{"1", "y"}));
  EXPECT_EQ(grid.points[3], (std::vector<std::string>{"2", "x"}));
  EXPECT_THROW(GridPoints({"a", "b"}, {{"1", "2"}, {"x", "y", "z"}}, 5, "grid"), InputError);
  EXPECT_THROW(GridPoints({"a", "a"}, {{"1"}, {"2"}}, 100, "grid"), InputError);
  EXPECT_THROW(GridPoints({"a"}, {{}}, 100, "grid"), InputError);
}

TEST(SpecOverrideTest, ExpandingNamesTheBadPointAndCanTakeASlice) {
  const SweepPoints sweep = GridPoints({"rtol", "drives[0].pd_servo.kp"},
                                       {{"1e-6", "1e-8"}, {"10", "oops", "30"}}, 100, "grid");
  try {
    ExpandSweep(Servo(), sweep, "sweep");
    FAIL() << "a string for kp was accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("sweep: point 1 (rtol=1e-6, drives[0].pd_servo.kp=oops)"));
  }
  const std::vector<v1::RunSpec> slice = ExpandSweep(Servo(), sweep, "sweep", 2, 2);
  ASSERT_EQ(slice.size(), 2u);
  EXPECT_EQ(slice[0].drives(0).pd_servo().kp(), 30.0);
  EXPECT_EQ(slice[1].rtol(), 1e-8);
  EXPECT_EQ(slice[1].drives(0).pd_servo().kp(), 10.0);
}

}  // namespace
}  // namespace mbstream

// SweepPlan: a stored sweep's points expanded one at a time from its definition, in the order
// GridPoints lists them (the first axis varying slowest), with nothing kept per point; its
// checks name what to change.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "server/runs/sweep_plan.h"
#include "server/spec/spec_override.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

using ::testing::HasSubstr;

v1::SweepDefinition Grid(
    const std::vector<std::pair<std::string, std::vector<std::string>>>& axes) {
  v1::SweepDefinition definition;
  for (const auto& [path, values] : axes) {
    v1::SweepDefinition::Axis& axis = *definition.add_grid();
    axis.set_path(path);
    for (const std::string& value : values) axis.add_values(value);
  }
  return definition;
}

TEST(SweepPlanTest, AGridsPointsComeInGridPointsOrder) {
  const SweepPlan plan(Grid({{"rtol", {"1e-6", "1e-8"}}, {"duration_s", {"1", "2", "3"}}}));
  ASSERT_EQ(plan.size(), 6);
  const SweepPoints all =
      GridPoints({"rtol", "duration_s"}, {{"1e-6", "1e-8"}, {"1", "2", "3"}}, 100, "grid");
  for (long k = 0; k < plan.size(); ++k) EXPECT_EQ(plan.Values(k), all.points[k]) << k;
  EXPECT_EQ(plan.Label(4), "rtol=1e-8, duration_s=2");
  const v1::RunSpec spec = plan.Spec(5, "sweep");
  EXPECT_DOUBLE_EQ(spec.rtol(), 1e-8);
  EXPECT_DOUBLE_EQ(spec.duration_s(), 3.0);
}

TEST(SweepPlanTest, AHundredThousandPointGridCostsItsAxesOnly) {
  std::vector<std::string> kps, kds;
  for (int i = 0; i < 1000; ++i) kps.push_back(std::to_string(i));
  for (int i = 0; i < 100; ++i) kds.push_back(std::to_string(i));
  const SweepPlan plan(Grid({{"drives[0].pd_servo.kp", kps}, {"drives[0].pd_servo.kd", kds}}));
  EXPECT_EQ(plan.size(), 100'000);
  EXPECT_EQ(plan.definition().ByteSizeLong(),
            Grid({{"drives[0].pd_servo.kp", kps}, {"drives[0].pd_servo.kd", kds}}).ByteSizeLong());
  EXPECT_EQ(plan.Values(99'999), (std::vector<std::string>{"999", "99"}));
  EXPECT_EQ(plan.Values(12'345), (std::vector<std::string>{"123", "45"}));
  EXPECT_THROW(SweepPlan(Grid({{"rtol", kps}, {"atol", kps}})), InputError);  // 1,000,000
}

TEST(SweepPlanTest, AListsPointsAreItsRows) {
  v1::SweepDefinition definition;
  definition.add_list_paths("rtol");
  definition.add_list()->add_values("1e-6");
  definition.add_list()->add_values("-1");
  const SweepPlan plan(definition);
  EXPECT_EQ(plan.size(), 2);
  EXPECT_EQ(plan.Values(1), std::vector<std::string>{"-1"});
  definition.add_list()->add_values("1e-7");
  definition.mutable_list(2)->add_values("extra");
  try {
    SweepPlan bad(definition);
    FAIL() << "a row of two values for one path";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("point 2 has 2 values for 1 paths"));
  }
}

TEST(SweepPlanTest, ABadDefinitionSaysWhatToChange) {
  auto message = [](const v1::SweepDefinition& definition) {
    try {
      SweepPlan plan(definition);
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  EXPECT_THAT(message(v1::SweepDefinition()), HasSubstr("give grid axes or list points"));
  EXPECT_THAT(message(Grid({{"rtol", {}}})), HasSubstr("rtol has no values"));
  EXPECT_THAT(message(Grid({{"rtol", {"1"}}, {"rtol", {"2"}}})), HasSubstr("swept twice"));
  v1::SweepDefinition both = Grid({{"rtol", {"1"}}});
  both.add_list_paths("atol");
  EXPECT_THAT(message(both), HasSubstr("not both"));
  const SweepPlan plan(Grid({{"drives[9].pd_servo.kp", {"1"}}}));
  try {
    plan.Spec(0, "sweep");
    FAIL() << "no drive 9 in an empty base spec";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("sweep: point 0 (drives[9].pd_servo.kp=1)"));
  }
}

}  // namespace
}  // namespace mbstream

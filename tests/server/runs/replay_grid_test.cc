// The common time grid of a replay and its ghost, and the refusals that name what to do.
#include <gmock/gmock.h>

#include "server/runs/replay_grid.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

using ::testing::HasSubstr;

ReplayGridRun GridRun(const std::string& id, int64_t frames, double interval_s) {
  return {id, frames, interval_s, {"j1", "j2"}};
}

std::string Refusal(const ReplayGridRun& a, const ReplayGridRun& b) {
  try {
    AlignReplayGrids(a, b);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ReplayGridTest, TheCoarserIntervalOverTheShorterRun) {
  const ReplayGrid grid = AlignReplayGrids(GridRun("a", 401, 0.05), GridRun("b", 1001, 0.01));
  EXPECT_EQ(grid.stride, 1);
  EXPECT_EQ(grid.ghost_stride, 5);
  EXPECT_EQ(grid.frames, 201);  // b ends at 10 s
  EXPECT_DOUBLE_EQ(grid.interval_s, 0.05);
  const ReplayGrid reverse = AlignReplayGrids(GridRun("b", 1001, 0.01), GridRun("a", 401, 0.05));
  EXPECT_EQ(reverse.stride, 5);
  EXPECT_EQ(reverse.ghost_stride, 1);
  EXPECT_EQ(reverse.frames, 201);
  const ReplayGrid same = AlignReplayGrids(GridRun("a", 401, 0.05), GridRun("b", 401, 0.05));
  EXPECT_EQ(same.stride, 1);
  EXPECT_EQ(same.ghost_stride, 1);
  EXPECT_EQ(same.frames, 401);
  // 0.1 / 0.02 is 5.000000000000001 in doubles: a whole multiple all the same.
  EXPECT_EQ(AlignReplayGrids(GridRun("a", 11, 0.1), GridRun("b", 51, 0.02)).ghost_stride, 5);
  EXPECT_EQ(SingleRunGrid(GridRun("a", 7, 0.5)).frames, 7);
}

TEST(ReplayGridTest, RefusalsNameBothRunsAndWhatToDo) {
  EXPECT_THAT(Refusal(GridRun("r-a", 401, 0.05), GridRun("r-b", 601, 0.03)),
              HasSubstr("cannot compare run r-a with run r-b: their time grids cannot be aligned "
                        "(a frame every 0.05 s against every 0.03 s); run r-b's model again "
                        "with --output-interval 0.05 or a whole fraction of it"));
  ReplayGridRun other = GridRun("r-b", 401, 0.05);
  other.joint_names = {"j1", "elbow"};
  EXPECT_THAT(Refusal(GridRun("r-a", 401, 0.05), other),
              HasSubstr("their models' joints differ (j1,j2 against j1,elbow)"));
  EXPECT_THAT(Refusal(GridRun("r-a", 401, 0.05), GridRun("r-b", 0, 0.0)),
              HasSubstr("run r-b has no stored frames"));
}

}  // namespace
}  // namespace mbstream

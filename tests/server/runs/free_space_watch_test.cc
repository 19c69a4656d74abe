// FreeSpaceWatch: `enough` against the minimum (unknown free space counts as enough), the
// listener told once when set and then only on a change.
#include "server/runs/free_space_watch.h"

#include <gtest/gtest.h>

#include <vector>

namespace mbstream {
namespace {

TEST(FreeSpaceWatchTest, TellsTheListenerWhenEnoughChanges) {
  std::optional<int64_t> free = 100;
  FreeSpaceWatch watch([&] { return free; }, 50);
  std::vector<bool> told;
  watch.SetListener([&](bool enough) { told.push_back(enough); });
  EXPECT_EQ(told, std::vector<bool>({true}));
  EXPECT_TRUE(watch.Check());
  EXPECT_EQ(watch.free_bytes(), 100);
  free = 49;
  EXPECT_FALSE(watch.Check());
  EXPECT_FALSE(watch.Check());  // no change: not told again
  EXPECT_FALSE(watch.enough());
  free = 50;  // exactly the minimum: enough
  EXPECT_TRUE(watch.Check());
  free = std::nullopt;  // unknown (statvfs failed): runs are not refused either
  EXPECT_TRUE(watch.Check());
  EXPECT_EQ(watch.free_bytes(), std::nullopt);
  EXPECT_EQ(told, std::vector<bool>({true, false, true}));
}

TEST(FreeSpaceWatchTest, NoMinimumOrNoSourceIsAlwaysEnough) {
  FreeSpaceWatch no_minimum([] { return std::optional<int64_t>(0); }, 0);
  EXPECT_TRUE(no_minimum.Check());
  FreeSpaceWatch no_source({}, 64);
  EXPECT_TRUE(no_source.Check());
  no_source.Start(3600.0);  // checks at once, then stops without waiting an hour
  no_source.Stop();
  EXPECT_TRUE(no_source.enough());
}

}  // namespace
}  // namespace mbstream

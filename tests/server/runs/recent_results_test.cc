// RecentResults: results kept by run id, replaced whole, the oldest out first beyond the limit.
#include "server/runs/recent_results.h"

#include <gtest/gtest.h>

#include <string>

namespace mbstream {
namespace {

TEST(RecentResultsTest, KeepsTheNewestWithinItsBytesAndNeverAStaleCopy) {
  RecentResults recent(10);
  std::string out;
  EXPECT_FALSE(recent.Get("r-1", out));
  recent.Put("r-1", "aaaa");
  recent.Put("r-2", "bbbb");
  ASSERT_TRUE(recent.Get("r-1", out));
  EXPECT_EQ(out, "aaaa");
  EXPECT_EQ(recent.bytes(), 8u);

  recent.Put("r-3", "cccc");  // 12 bytes: r-1, the oldest, goes
  EXPECT_FALSE(recent.Get("r-1", out));
  ASSERT_TRUE(recent.Get("r-2", out));
  EXPECT_EQ(out, "bbbb");
  EXPECT_EQ(recent.bytes(), 8u);

  recent.Put("r-2", "BB");  // replaced
  ASSERT_TRUE(recent.Get("r-2", out));
  EXPECT_EQ(out, "BB");
  EXPECT_EQ(recent.bytes(), 6u);

  recent.Put("r-3", std::string(11, 'x'));  // too big to keep: not kept, nor its old copy
  EXPECT_FALSE(recent.Get("r-3", out));
  EXPECT_TRUE(recent.Get("r-2", out));
  EXPECT_EQ(recent.bytes(), 2u);

  RecentResults none(0);
  none.Put("r-1", "a");
  EXPECT_FALSE(none.Get("r-1", out));
}

}  // namespace
}  // namespace mbstream

// RecentResults: results kept by run id with their final info, replaced whole, the oldest out
// first beyond the limit.
#include "server/runs/recent_results.h"

#include <gtest/gtest.h>

#include <string>

namespace mbstream {
namespace {

v1::RunInfo Ended(const std::string& id) {
  v1::RunInfo info;
  info.set_id(id);
  info.set_state(v1::FINISHED);
  return info;
}

TEST(RecentResultsTest, KeepsTheNewestWithinItsBytesAndNeverAStaleCopy) {
  const std::size_t info_bytes = Ended("r-1").ByteSizeLong();  // the same for r-2 and r-3
  RecentResults recent(10 + 2 * info_bytes);
  std::string out;
  v1::RunInfo info;
  EXPECT_FALSE(recent.Get("r-1", out));
  EXPECT_FALSE(recent.GetInfo("r-1", info));
  recent.Put(Ended("r-1"), "aaaa");
  recent.Put(Ended("r-2"), "bbbb");
  ASSERT_TRUE(recent.Get("r-1", out));
  EXPECT_EQ(out, "aaaa");
  ASSERT_TRUE(recent.GetInfo("r-1", info));
  EXPECT_EQ(info.id(), "r-1");
  EXPECT_EQ(info.state(), v1::FINISHED);
  EXPECT_EQ(recent.bytes(), 8u + 2 * info_bytes);

  recent.Put(Ended("r-3"), "cccc");  // 12 bytes and 3 infos: r-1, the oldest, goes
  EXPECT_FALSE(recent.Get("r-1", out));
  EXPECT_FALSE(recent.GetInfo("r-1", info));
  ASSERT_TRUE(recent.Get("r-2", out));
  EXPECT_EQ(out, "bbbb");
  EXPECT_EQ(recent.bytes(), 8u + 2 * info_bytes);

  v1::RunInfo failed = Ended("r-2");
  failed.set_state(v1::FAILED);
  recent.Put(failed, "BB");  // replaced, info and frames
  ASSERT_TRUE(recent.Get("r-2", out));
  EXPECT_EQ(out, "BB");
  ASSERT_TRUE(recent.GetInfo("r-2", info));
  EXPECT_EQ(info.state(), v1::FAILED);
  EXPECT_EQ(recent.bytes(), 6u + 2 * info_bytes);

  // Too big to keep: not kept, nor its old copy.
  recent.Put(Ended("r-3"), std::string(11 + info_bytes, 'x'));
  EXPECT_FALSE(recent.Get("r-3", out));
  EXPECT_FALSE(recent.GetInfo("r-3", info));
  EXPECT_TRUE(recent.Get("r-2", out));
  EXPECT_EQ(recent.bytes(), 2u + info_bytes);

  RecentResults none(0);
  none.Put(Ended("r-1"), "a");
  EXPECT_FALSE(none.Get("r-1", out));
  EXPECT_FALSE(none.GetInfo("r-1", info));
}

}  // namespace
}  // namespace mbstream

// Store::Usage on both backends: runs by model and state, the bytes of their frames, probe
// reports and rows, what deleting some would free, and what a deletion gives back.
#include <gmock/gmock.h>

#include "server/store/frame_chunks.h"
#include "server/store/store.h"
#include "tests/server/store/store_test_util.h"

namespace mbstream::testing {
namespace {

class StoreUsageTest : public testing::StoreBackendTest {};
INSTANTIATE_STORE_BACKENDS(StoreUsageTest);

int64_t ProbeBytes(const std::string& id) {
  return static_cast<int64_t>(MakeProbe(id, 0, "tcp").ByteSizeLong() +
                              MakeProbe(id, 1, "tcp").ByteSizeLong() +
                              MakeProbe(id, 3, "tcp").ByteSizeLong());
}

int64_t FrameBytes(int64_t frames) {
  int64_t bytes = 0;
  for (const EncodedFrameChunk& chunk : EncodeFrameChunks(MakeFrames(frames, 2))) {
    bytes += static_cast<int64_t>(chunk.data.size());
  }
  return bytes;
}

TEST_P(StoreUsageTest, CountsRunsAndBytesByModelAndState) {
  auto store = Open();
  EXPECT_EQ(store->Usage({}).frame_bytes, 0);
  StoreWholeRun(*store, "r-1", kFramesPerChunk + 5, "m-a");
  StoreWholeRun(*store, "r-2", 7, "m-a");
  StoreWholeRun(*store, "r-3", 3, "m-b");
  v1::RunInfo queued = MakeRun("r-4", v1::QUEUED, 2);
  queued.set_model_id("m-b");
  ASSERT_TRUE(store->AddRuns({queued}));

  const StoreUsage usage = store->Usage({"r-1", "r-unknown"});
  EXPECT_EQ(usage.runs_by_state, (std::map<int, int64_t>{{v1::QUEUED, 1}, {v1::FINISHED, 3}}));
  ASSERT_EQ(usage.models.size(), 2u);
  EXPECT_EQ(usage.models.at("m-a").runs, 2);
  EXPECT_EQ(usage.models.at("m-b").runs, 2);
  EXPECT_EQ(usage.models.at("m-a").frame_bytes, FrameBytes(kFramesPerChunk + 5) + FrameBytes(7));
  EXPECT_EQ(usage.models.at("m-b").frame_bytes, FrameBytes(3));
  EXPECT_EQ(usage.models.at("m-a").probe_bytes, ProbeBytes("r-1") + ProbeBytes("r-2"));
  EXPECT_EQ(usage.frame_bytes, FrameBytes(kFramesPerChunk + 5) + FrameBytes(7) + FrameBytes(3));
  EXPECT_EQ(usage.probe_bytes, ProbeBytes("r-1") + ProbeBytes("r-2") + ProbeBytes("r-3"));
  EXPECT_GT(usage.run_bytes, 4 * 20);
  EXPECT_EQ(usage.weighed_bytes, FrameBytes(kFramesPerChunk + 5) + ProbeBytes("r-1"));
  if (backend() == Backend::kSqlite) {
    EXPECT_GT(usage.disk_bytes, usage.frame_bytes);
  } else {
    EXPECT_EQ(usage.disk_bytes, 0);  // the database server's disk
  }

  ASSERT_TRUE(store->DeleteRun("r-1"));
  const StoreUsage after = store->Usage({"r-1"});
  EXPECT_EQ(after.models.at("m-a").runs, 1);
  EXPECT_EQ(after.frame_bytes, FrameBytes(7) + FrameBytes(3));
  EXPECT_EQ(after.weighed_bytes, 0);
}

}  // namespace
}  // namespace mbstream::testing

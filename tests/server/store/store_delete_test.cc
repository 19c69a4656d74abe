// Store: deleting a run (row, frames, probes, probe sets: one transaction) and a model (refused
// while runs of it remain), on both backends; a reader sees a run whole or not at all.
#include <atomic>
#include <thread>

#include <gmock/gmock.h>

#include "server/store/frame_chunks.h"
#include "server/store/store.h"
#include "tests/server/store/store_test_util.h"

namespace mbstream::testing {
namespace {

class StoreDeleteTest : public testing::StoreBackendTest {};
INSTANTIATE_STORE_BACKENDS(StoreDeleteTest);

TEST_P(StoreDeleteTest, DeleteRunRemovesAllOfItAndNothingElse) {
  auto store = Open();
  StoreWholeRun(*store, "r-1", kFramesPerChunk + 5);
  StoreWholeRun(*store, "r-2", 7);

  EXPECT_TRUE(store->DeleteRun("r-1"));
  EXPECT_FALSE(store->GetRun("r-1"));
  std::string data;
  EXPECT_FALSE(store->GetFrameChunkData("r-1", 0, data));
  EXPECT_TRUE(store->GetProbes("r-1").empty());
  EXPECT_TRUE(store->ListProbeSets("r-1").empty());
  EXPECT_FALSE(store->GetProbeSet("ps-r-1"));
  EXPECT_TRUE(store->GetProbeSetReports("ps-r-1").empty());
  EXPECT_FALSE(store->DeleteRun("r-1"));  // gone already
  EXPECT_FALSE(store->DeleteRun("r-unknown"));

  store.reset();  // and after a restart
  store = Open();
  EXPECT_FALSE(store->GetRun("r-1"));
  ASSERT_EQ(store->ListRuns().size(), 1u);
  EXPECT_EQ(store->GetFrames("r-2").size(), 7u);
  EXPECT_EQ(store->GetProbes("r-2").size(), 2u);
  EXPECT_EQ(store->GetProbeSetReports("ps-r-2").size(), 1u);
}

TEST_P(StoreDeleteTest, DeleteModelWaitsUntilItHasNoRuns) {
  auto store = Open();
  ASSERT_TRUE(store->PutModel(MakeModelInfo("m-abc", 1), MakeBundle("arm", 2)));
  ASSERT_TRUE(store->PutModel(MakeModelInfo("m-other", 2), MakeBundle("other", 1)));
  StoreWholeRun(*store, "r-1", 3);  // a run of m-abc

  EXPECT_EQ(store->DeleteModel("m-abc"), 1);  // refused: nothing deleted
  EXPECT_EQ(store->ListModels().size(), 2u);
  EXPECT_TRUE(store->GetModelBundle("m-abc"));

  ASSERT_TRUE(store->DeleteRun("r-1"));
  EXPECT_EQ(store->DeleteModel("m-abc"), 0);
  EXPECT_FALSE(store->GetModelBundle("m-abc"));
  ASSERT_EQ(store->ListModels().size(), 1u);
  EXPECT_EQ(store->ListModels()[0].id(), "m-other");
  EXPECT_EQ(store->ModelBytes().count("m-abc"), 0u);
  EXPECT_EQ(store->DeleteModel("m-abc"), 0);  // not stored: nothing to do
}

// A reader that reads a run chunk by chunk and then finds its row still stored has read all
// of it: the row goes in the transaction that deletes the rest (get_result.cc relies on it).
TEST_P(StoreDeleteTest, AReaderThatStillFindsTheRowReadItWhole) {
  auto store = Open();
  constexpr int kRuns = 12;
  constexpr int64_t kFrames = 3 * kFramesPerChunk;
  for (int i = 0; i < kRuns; ++i) StoreWholeRun(*store, "r-" + std::to_string(i), kFrames);
  std::atomic<int> read_whole{0};  // runs read whole once at least (then deleted)
  std::atomic<int> partial{0}, gone{0};
  std::thread reader([&] {
    for (int i = 0; i < kRuns; ++i) {
      const std::string id = "r-" + std::to_string(i);
      while (true) {  // reads run i until it is deleted
        const std::vector<v1::Frame> frames = store->GetFrames(id);
        const std::vector<v1::ProbeReport> probes = store->GetProbes(id);
        if (!store->GetRun(id)) {
          ++gone;
          break;
        }
        if (frames.size() == kFrames && probes.size() == 2) {
          if (read_whole.load() == i) read_whole = i + 1;
        } else {
          ++partial;
        }
      }
    }
  });
  for (int i = 0; i < kRuns; ++i) {  // each deleted while the reader reads it again
    while (read_whole.load() <= i) std::this_thread::yield();
    EXPECT_TRUE(store->DeleteRun("r-" + std::to_string(i)));
  }
  reader.join();
  EXPECT_EQ(partial.load(), 0);
  EXPECT_EQ(gone.load(), kRuns);
  EXPECT_TRUE(store->ListRuns().empty());
}

}  // namespace
}  // namespace mbstream::testing

// Store: the frames a run stored while it ran survive the server: a run left unfinished by a
// crash (or by a replica whose lease expired) is INTERRUPTED with its stored frames, and its
// row says how many and up to which time (issue 36 item 5).
#include <chrono>
#include <filesystem>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "server/store/frame_chunks.h"
#include "server/store/store.h"
#include "tests/server/store/store_test_util.h"

namespace mbstream {
namespace {

using ::testing::HasSubstr;
using testing::MakeFrames;
using testing::MakeRun;
using testing::Same;
using testing::TempDirectory;

class StoreKeptFramesTest : public testing::StoreBackendTest {};
INSTANTIATE_STORE_BACKENDS(StoreKeptFramesTest);

void ExpectSameFrames(const std::vector<v1::Frame>& got, const std::vector<v1::Frame>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].SerializeAsString(), want[i].SerializeAsString()) << "frame " << i;
  }
}

TEST_P(StoreKeptFramesTest, AnInterruptedRunKeepsItsStoredFramesAndItsRowCountsThem) {
  const std::vector<v1::Frame> frames = MakeFrames(7, 2);
  {
    auto store = Open();
    store->PutRun(MakeRun("r-running", v1::RUNNING, 1000));
    store->PutRun(MakeRun("r-queued", v1::QUEUED, 2000));
    const std::vector<EncodedFrameChunk> chunks = EncodeFrameChunks(frames, 4);  // 4 + 3
    for (int i = 0; i < 2; ++i) store->PutFrameChunk("r-running", i, chunks[i], "");
  }  // the kill
  auto store = Open();
  EXPECT_EQ(store->MarkUnfinishedRunsInterrupted("server restarted"), 2);

  const v1::RunInfo run = *store->GetRun("r-running");
  EXPECT_EQ(run.state(), v1::INTERRUPTED);
  EXPECT_EQ(run.frames(), 7);
  EXPECT_EQ(run.t_s(), frames.back().t_s());
  EXPECT_EQ(run.stats().t_reached_s(), frames.back().t_s());
  EXPECT_TRUE(run.has_torques());
  EXPECT_TRUE(run.has_energy());
  EXPECT_THAT(run.message(), HasSubstr("server restarted; the 7 frames stored up to t = 0.006 s"));
  ExpectSameFrames(store->GetFrames("r-running"), frames);

  const v1::RunInfo queued = *store->GetRun("r-queued");  // nothing stored: as before
  EXPECT_EQ(queued.state(), v1::INTERRUPTED);
  EXPECT_EQ(queued.frames(), 0);
  EXPECT_EQ(queued.message(), "server restarted");
  EXPECT_FALSE(queued.has_torques());
}

TEST_P(StoreKeptFramesTest, ARunWhoseLeaseExpiredKeepsItsStoredFramesInItsRow) {
  auto store = Open();
  store->PutRun(MakeRun("r-1", v1::RUNNING, 1000));  // no lease: expired, no retries left
  const std::vector<v1::Frame> frames = MakeFrames(5, 3);
  store->PutFrameChunk("r-1", 0, EncodeFrameChunks(frames).front(), "");
  const int64_t now_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                             std::chrono::system_clock::now().time_since_epoch())
                             .count();
  const std::vector<v1::RunInfo> reaped = store->ReapExpiredLeases(now_ms, "reaper-1");
  ASSERT_EQ(reaped.size(), 1u);
  EXPECT_EQ(reaped[0].state(), v1::INTERRUPTED);
  EXPECT_EQ(reaped[0].frames(), 5);
  EXPECT_EQ(reaped[0].stats().t_reached_s(), frames.back().t_s());
  EXPECT_TRUE(Same(*store->GetRun("r-1"), reaped[0]));
  ExpectSameFrames(store->GetFrames("r-1"), frames);
}

// A replica writes chunks only while it holds the run's lease: once the run was reaped (or
// taken over), its late chunks are refused and the kept frames stay as counted.
TEST_P(StoreKeptFramesTest, AChunkIsStoredOnlyWhileItsWriterHoldsTheLease) {
  auto store = Open();
  store->PutRun(MakeRun("r-1", v1::QUEUED, 1000));
  const v1::RunInfo claimed = *store->ClaimQueuedRun(RunLease{"a", "a:1", 1000, 5000});
  const std::string holder = LeaseHolder(claimed);
  const std::vector<EncodedFrameChunk> chunks = EncodeFrameChunks(MakeFrames(6, 2), 3);
  EXPECT_TRUE(store->PutFrameChunk("r-1", 0, chunks[0], holder));
  EXPECT_FALSE(store->PutFrameChunk("r-1", 0, chunks[1], "b/1"));  // not the holder
  const std::vector<v1::RunInfo> reaped = store->ReapExpiredLeases(5001, "b");
  ASSERT_EQ(reaped.size(), 1u);
  EXPECT_EQ(reaped[0].frames(), 3);
  EXPECT_FALSE(store->PutFrameChunk("r-1", 1, chunks[1], holder));  // too late
  EXPECT_EQ(store->GetFrames("r-1").size(), 3u);
  EXPECT_EQ(store->GetRun("r-1")->frames(), 3);
}

// An attempt's chunk replaces the earlier attempt's chunks from its number on, so that the
// stored chunks are always one attempt's frames, seq 0 onwards.
TEST_P(StoreKeptFramesTest, AStoredChunkRemovesTheChunksNumberedAfterIt) {
  auto store = Open();
  store->PutRun(MakeRun("r-1", v1::RUNNING, 1000));
  const std::vector<EncodedFrameChunk> first = EncodeFrameChunks(MakeFrames(12, 2), 4);
  for (int i = 0; i < 3; ++i) store->PutFrameChunk("r-1", i, first[i], "");
  const std::vector<v1::Frame> again = MakeFrames(6, 2);
  store->PutFrameChunk("r-1", 0, EncodeFrameChunks(again, 6).front(), "");
  ExpectSameFrames(store->GetFrames("r-1"), again);
  EXPECT_EQ(store->MarkUnfinishedRunsInterrupted("restart"), 1);
  EXPECT_EQ(store->GetRun("r-1")->frames(), 6);
}

// The machine stopped before the last chunk's bytes reached the frames file: that chunk is
// removed and the run keeps the frames before it, all readable.
TEST(StoreKeptFramesSqliteTest, ADamagedLastChunkIsDroppedAndTheRestKept) {
  TempDirectory temp;
  const std::vector<v1::Frame> frames = MakeFrames(8, 2);
  const std::vector<EncodedFrameChunk> chunks = EncodeFrameChunks(frames, 5);  // 5 + 3
  {
    auto store = Store::Open(temp.str());
    store->PutRun(MakeRun("r-1", v1::RUNNING, 1000));
    for (int i = 0; i < 2; ++i) store->PutFrameChunk("r-1", i, chunks[i], "");
  }
  const std::filesystem::path file = temp.path() / Store::kFramesFileName;
  ASSERT_EQ(std::filesystem::file_size(file), chunks[0].data.size() + chunks[1].data.size());
  std::filesystem::resize_file(file, chunks[0].data.size() + chunks[1].data.size() / 2);

  auto store = Store::Open(temp.str());
  EXPECT_EQ(store->MarkUnfinishedRunsInterrupted("restart"), 1);
  const v1::RunInfo run = *store->GetRun("r-1");
  EXPECT_EQ(run.frames(), 5);
  EXPECT_EQ(run.t_s(), frames[4].t_s());
  EXPECT_THAT(run.message(), HasSubstr("1 later chunks of frames were damaged"));
  ExpectSameFrames(store->GetFrames("r-1"),
                   std::vector<v1::Frame>(frames.begin(), frames.begin() + 5));
}

}  // namespace
}  // namespace mbstream

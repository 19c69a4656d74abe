// A run's frames go to the store while it runs (a run keeps only a window of them), and
// GetResult streams a large result chunk by chunk with every frame.
#include <gmock/gmock.h>

#include <thread>

#include "server/store/frame_chunks.h"
#include "server/store/store.h"
#include "server/wire/stats_conversion.h"
#include "tests/server/service/server_fixture.h"

namespace mbstream::testing {
namespace {

class FrameStorageTest : public ServerTest {
 protected:
  void SetUp() override { StartServer(); }

  v1::RunInfo GetRun(const std::string& run_id) {
    grpc::ClientContext context;
    v1::GetRunRequest request;
    request.set_run_id(run_id);
    v1::RunInfo info;
    const grpc::Status status = stub().GetRun(&context, request, &info);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return info;
  }

  std::unique_ptr<Store> OpenStore() { return Store::Open((data_.path() / "data").string()); }
};

// The frame after a full chunk is published only once that chunk is stored (the run's
// thread stores it between the two), so waiting for it needs no timing assumption. The run
// is paced at 10x real time over 1000 s of simulated time: it cannot end while the test
// looks at it.
TEST_F(FrameStorageTest, FramesAreStoredWhileTheRunRuns) {
  v1::RunSpec spec = SceneSpec("seed-run.json");
  spec.set_duration_s(1000.0);
  spec.set_output_interval_s(1e-3);
  spec.set_realtime(10.0);
  const v1::RunInfo started = StartRunOk("irb1600", spec);
  const int64_t chunk = static_cast<int64_t>(kFramesPerChunk);
  v1::RunInfo info = GetRun(started.id());
  while (info.frames() <= chunk && !IsFinalState(info.state())) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    info = GetRun(started.id());
  }
  ASSERT_EQ(info.state(), v1::RUNNING) << info.message();

  std::unique_ptr<Store> store = OpenStore();  // a second connection to the server's file
  std::vector<v1::Frame> stored;
  const std::optional<int64_t> next = store->GetFrameChunk(started.id(), 0, stored);
  ASSERT_TRUE(next.has_value()) << "no frames in the store while the run is running";
  ASSERT_EQ(stored.size(), kFramesPerChunk);
  for (int64_t k = 0; k < chunk; ++k) ASSERT_EQ(stored[k].seq(), k);
  // The row is not final: a private store's run stays QUEUED there until it ends (its claim
  // is made in the server's memory, RunQueue::ClaimPrivate); the server says RUNNING.
  EXPECT_EQ(store->GetRun(started.id())->state(), v1::QUEUED);
  EXPECT_EQ(GetRun(started.id()).state(), v1::RUNNING);

  // GetResult of a running run is refused; after the cancel every frame is there.
  std::vector<v1::Frame> frames;
  EXPECT_EQ(Result(started.id(), &info, &frames, nullptr).error_code(),
            grpc::StatusCode::FAILED_PRECONDITION);
  {
    grpc::ClientContext context;
    v1::CancelRunRequest request;
    request.set_run_id(started.id());
    v1::RunInfo cancelled;
    ASSERT_TRUE(stub().CancelRun(&context, request, &cancelled).ok());
  }
  const v1::RunInfo ended = WaitForEnd(started.id());
  ASSERT_EQ(ended.state(), v1::CANCELLED) << ended.message();
  frames.clear();
  ASSERT_TRUE(Result(started.id(), &info, &frames, nullptr).ok());
  ASSERT_EQ(static_cast<int64_t>(frames.size()), ended.frames());
  EXPECT_GT(ended.frames(), chunk);
  for (size_t k = 0; k < frames.size(); ++k) ASSERT_EQ(frames[k].seq(), static_cast<int64_t>(k));
}

TEST_F(FrameStorageTest, GetResultOfALargeRunArrivesInChunksWithEveryFrame) {
  v1::RunSpec spec = SceneSpec("seed-run.json");
  spec.set_output_interval_s(1e-3);  // 20 s: 20,001 frames, five stored chunks
  const v1::RunInfo started = StartRunOk("irb1600", spec);
  ASSERT_EQ(started.expected_frames(), 20001);
  const v1::RunInfo ended = WaitForEnd(started.id());
  ASSERT_EQ(ended.state(), v1::FINISHED) << ended.message();

  grpc::ClientContext context;
  v1::GetResultRequest request;
  request.set_run_id(started.id());
  auto reader = stub().GetResult(&context, request);
  v1::ResultChunk chunk;
  int messages_with_frames = 0;
  size_t largest_message = 0;
  int64_t next_seq = 0;
  bool info_first = false;
  for (int message = 0; reader->Read(&chunk); ++message) {
    if (message == 0) info_first = chunk.has_info();
    if (message > 0) {
      EXPECT_FALSE(chunk.has_info()) << "the info again in message " << message;
    }
    if (chunk.frames_size() > 0) ++messages_with_frames;
    largest_message = std::max(largest_message, chunk.ByteSizeLong());
    for (const v1::Frame& frame : chunk.frames()) {
      ASSERT_EQ(frame.seq(), next_seq) << "a frame is missing or out of order";
      ++next_seq;
    }
  }
  ASSERT_TRUE(reader->Finish().ok());
  EXPECT_TRUE(info_first);
  EXPECT_EQ(next_seq, 20001);
  EXPECT_GE(messages_with_frames, 3);
  EXPECT_LT(largest_message, 2u << 20);  // about 1 MiB each
  std::vector<v1::Frame> last;
  EXPECT_EQ(OpenStore()->GetFrameChunk(started.id(), 4, last).value_or(-1), 5);
  EXPECT_EQ(last.back().seq(), 20000);
}

}  // namespace
}  // namespace mbstream::testing

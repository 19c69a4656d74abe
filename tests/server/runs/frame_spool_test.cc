// FrameSpool: a chunk's buffer is sized once, from the run's expected frame count; a chunk
// goes to the store when it is full or when the flush interval has passed (manual clock).
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "server/runs/frame_spool.h"
#include "server/store/store.h"
#include "tests/common/allocation_counter.h"
#include "tests/server/runs/manual_run_clock.h"

namespace mbstream {
namespace {

namespace fs = std::filesystem;

v1::Frame MakeFrame(int64_t seq) {
  v1::Frame frame;
  frame.set_seq(seq);
  frame.set_t_s(0.05 * static_cast<double>(seq));  // frame 0: zero, not serialized; seq too
  for (int j = 0; j < 6; ++j) {
    frame.add_q(0.1 * j + 1e-3 * static_cast<double>(seq));
    frame.add_qd(-0.2 * j);
    frame.add_tau(10.0 * j + 1.0);
  }
  frame.mutable_tcp_m()->set_x(0.5);
  frame.set_kinetic_j(0.3 * static_cast<double>(seq));  // frame 0 lacks these two as well
  frame.set_potential_j(0.1 * static_cast<double>(seq));
  return frame;
}

TEST(FrameSpoolTest, OneAllocationPerChunk) {
  const fs::path dir = fs::temp_directory_path() / ("mbstream-spool-" + std::to_string(getpid()));
  fs::remove_all(dir);
  {
    auto store = Store::Open(dir.string());
    v1::RunInfo info;
    info.set_id("r-1");
    store->PutRun(info);
    constexpr int64_t kFrames = 4000;
    FrameSpool spool("r-1", kFrames);
    std::vector<v1::Frame> frames;
    for (int64_t seq = 0; seq < kFrames; ++seq) frames.push_back(MakeFrame(seq));
    const long before = testing::AllocationCount();
    for (const v1::Frame& frame : frames) spool.Add(frame, *store);
    EXPECT_EQ(testing::AllocationCount() - before, 1);
    EXPECT_TRUE(spool.error().empty());
    info.set_state(v1::FINISHED);
    spool.Finish(info, *store);
    EXPECT_EQ(store->GetFrames("r-1").size(), static_cast<std::size_t>(kFrames));
  }
  fs::remove_all(dir);
}

// The result of a run stored whole in its final transaction is handed on as stored; one
// stored in several chunks is not.
TEST(FrameSpoolTest, HandsOnAResultStoredWholeInItsOneChunk) {
  const fs::path dir = fs::temp_directory_path() / ("mbstream-spool-w-" + std::to_string(getpid()));
  fs::remove_all(dir);
  {
    auto store = Store::Open(dir.string());
    for (const int64_t frames : {10, 25}) {
      v1::RunInfo info;
      info.set_id("r-" + std::to_string(frames));
      store->PutRun(info);
      FrameSpool spool(info.id(), frames, /*frames_per_chunk=*/20);
      for (int64_t seq = 0; seq < frames; ++seq) spool.Add(MakeFrame(seq), *store);
      info.set_state(v1::FINISHED);
      ASSERT_TRUE(spool.Finish(info, *store));
      const std::string whole = spool.TakeWholeResult();
      if (frames > 20) {
        EXPECT_TRUE(whole.empty());
        continue;
      }
      std::string stored;
      std::vector<std::string_view> stored_frames;
      EXPECT_EQ(store->GetSerializedFrames(info.id(), 0, stored, stored_frames),
                std::optional<int64_t>(1));  // one chunk, the last
      EXPECT_EQ(whole, stored);
      EXPECT_TRUE(spool.TakeWholeResult().empty());  // moved out once
    }
  }
  fs::remove_all(dir);
}

// The frames of `store`'s run `run_id`, serialized, for a bit-for-bit comparison.
std::vector<std::string> StoredBytes(const Store& store, const std::string& run_id) {
  std::vector<std::string> bytes;
  for (const v1::Frame& frame : store.GetFrames(run_id)) bytes.push_back(frame.SerializeAsString());
  return bytes;
}

std::vector<std::string> Bytes(const std::vector<v1::Frame>& frames, std::size_t count) {
  std::vector<std::string> bytes;
  for (std::size_t i = 0; i < count; ++i) bytes.push_back(frames[i].SerializeAsString());
  return bytes;
}

// A paced run's frames reach the store once a second of its clock has passed, long before a
// 4,096-frame chunk fills: a crash loses at most that second.
TEST(FrameSpoolTest, StoresAChunkWhenTheFlushIntervalHasPassed) {
  using std::chrono::milliseconds;
  const fs::path dir = fs::temp_directory_path() / ("mbstream-spool-t-" + std::to_string(getpid()));
  fs::remove_all(dir);
  {
    auto store = Store::Open(dir.string());
    v1::RunInfo info;
    info.set_id("r-1");
    store->PutRun(info);
    std::vector<v1::Frame> frames;
    for (int64_t seq = 0; seq < 30; ++seq) frames.push_back(MakeFrame(seq));
    testing::ManualRunClock clock;
    FrameSpool spool("r-1", static_cast<int64_t>(frames.size()));
    spool.FlushEvery(clock, std::chrono::seconds(1), clock.Now());

    for (int i = 0; i < 10; ++i) {  // frames 0..9 over 0.9 s: none due yet
      spool.Add(frames[static_cast<std::size_t>(i)], *store);
      clock.Advance(milliseconds(100));
    }
    EXPECT_EQ(spool.stored_chunks(), 0);
    EXPECT_TRUE(store->GetFrames("r-1").empty());
    spool.Add(frames[10], *store);  // at 1.0 s: frames 0..10 go, 11 of 4,096
    EXPECT_EQ(spool.stored_chunks(), 1);
    EXPECT_EQ(spool.stored_frames(), 11);
    EXPECT_EQ(StoredBytes(*store, "r-1"), Bytes(frames, 11));

    clock.Advance(milliseconds(999));
    spool.Add(frames[11], *store);  // 0.999 s after the last chunk: kept
    EXPECT_EQ(spool.stored_chunks(), 1);
    clock.Advance(milliseconds(1));
    spool.Add(frames[12], *store);  // 1 s after it: stored
    EXPECT_EQ(spool.stored_chunks(), 2);
    EXPECT_EQ(spool.stored_frames(), 13);
    EXPECT_EQ(StoredBytes(*store, "r-1"), Bytes(frames, 13));

    for (std::size_t i = 13; i < frames.size(); ++i) spool.Add(frames[i], *store);
    EXPECT_EQ(spool.stored_chunks(), 2);  // no time passed
    info.set_state(v1::FINISHED);
    ASSERT_TRUE(spool.Finish(info, *store));
    EXPECT_EQ(spool.stored_chunks(), 3);
    EXPECT_EQ(spool.stored_frames(), 30);
    EXPECT_TRUE(spool.TakeWholeResult().empty());  // not stored whole in one chunk
    // Stored in three chunks, read back as one run: the same bytes as one chunk.
    EXPECT_EQ(StoredBytes(*store, "r-1"), Bytes(frames, frames.size()));
    EXPECT_TRUE(spool.error().empty());
  }
  fs::remove_all(dir);
}

// A full chunk starts the interval again; an interval of 0 stores full chunks only.
TEST(FrameSpoolTest, AFullChunkRestartsTheIntervalAndZeroMeansFullChunksOnly) {
  using std::chrono::milliseconds;
  const fs::path dir = fs::temp_directory_path() / ("mbstream-spool-f-" + std::to_string(getpid()));
  fs::remove_all(dir);
  {
    auto store = Store::Open(dir.string());
    for (const char* id : {"r-1", "r-0"}) {
      v1::RunInfo info;
      info.set_id(id);
      store->PutRun(info);
    }
    testing::ManualRunClock clock;
    FrameSpool spool("r-1", 0, /*frames_per_chunk=*/4);
    spool.FlushEvery(clock, milliseconds(500), clock.Now());
    FrameSpool never("r-0", 0, /*frames_per_chunk=*/4);
    never.FlushEvery(clock, milliseconds(0), clock.Now());
    clock.Advance(milliseconds(400));
    for (int64_t seq = 0; seq < 4; ++seq) {  // full at 0.4 s
      spool.Add(MakeFrame(seq), *store);
      never.Add(MakeFrame(seq), *store);
    }
    EXPECT_EQ(spool.stored_chunks(), 1);
    EXPECT_EQ(never.stored_chunks(), 1);
    clock.Advance(milliseconds(400));  // 0.8 s: 0.4 s after the full chunk, not 0.5
    spool.Add(MakeFrame(4), *store);
    never.Add(MakeFrame(4), *store);
    EXPECT_EQ(spool.stored_chunks(), 1);
    clock.Advance(milliseconds(100));
    spool.Add(MakeFrame(5), *store);
    never.Add(MakeFrame(5), *store);
    EXPECT_EQ(spool.stored_chunks(), 2);
    EXPECT_EQ(spool.stored_frames(), 6);
    EXPECT_EQ(never.stored_chunks(), 1);  // 0.9 s later, 2 of 4 frames: kept
    EXPECT_EQ(never.stored_frames(), 4);
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mbstream

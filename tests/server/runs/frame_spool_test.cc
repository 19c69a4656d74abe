// FrameSpool: a chunk's buffer is sized once, from the run's expected frame count.
#include <unistd.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "server/runs/frame_spool.h"
#include "server/store/store.h"
#include "tests/common/allocation_counter.h"

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

}  // namespace
}  // namespace mbstream

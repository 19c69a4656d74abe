// Store: frames round trip in seq order, FinishRun is atomic, and the chunk codec.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "server/store/frame_chunks.h"
#include "server/store/sqlite_connection.h"
#include "server/store/sqlite_statement.h"
#include "server/store/store.h"
#include "shared/common/check.h"
#include "tests/server/store/store_test_util.h"

namespace mbstream {
namespace {

using ::testing::HasSubstr;
using testing::MakeFrames;
using testing::MakeRun;
using testing::Same;
using testing::TempDirectory;

void ExpectSameFrames(const std::vector<v1::Frame>& actual, const std::vector<v1::Frame>& want) {
  ASSERT_EQ(actual.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) {
    ASSERT_TRUE(Same(actual[i], want[i])) << "frame " << i;
  }
}

class StoreFramesTest : public testing::StoreBackendTest {};
INSTANTIATE_STORE_BACKENDS(StoreFramesTest);

TEST(FrameChunksTest, SplitsAndDecodes) {
  const std::vector<v1::Frame> frames = MakeFrames(10, 3);
  const auto chunks = EncodeFrameChunks(frames, 4);
  ASSERT_EQ(chunks.size(), 3u);
  EXPECT_EQ(chunks[1].first_seq, 4);
  EXPECT_EQ(chunks[2].frame_count, 2);
  std::vector<v1::Frame> decoded;
  for (const auto& chunk : chunks) ASSERT_TRUE(DecodeFrameChunk(chunk.data, decoded));
  ExpectSameFrames(decoded, frames);
}

TEST(FrameChunksTest, TruncatedChunkIsReportedCorrupt) {
  const auto chunks = EncodeFrameChunks(MakeFrames(3, 2));
  std::vector<v1::Frame> decoded;
  EXPECT_FALSE(DecodeFrameChunk(
      std::string_view(chunks[0].data).substr(0, chunks[0].data.size() - 3), decoded));
}

// GetResult sends the stored bytes: each split frame is the frame's own serialization.
TEST(FrameChunksTest, SplitGivesEachFrameAsSerialized) {
  const std::vector<v1::Frame> frames = MakeFrames(10, 6);
  const auto chunks = EncodeFrameChunks(frames, 4);
  std::vector<std::string_view> split;
  for (const auto& chunk : chunks) ASSERT_TRUE(SplitFrameChunk(chunk.data, split));
  ASSERT_EQ(split.size(), frames.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(split[i], frames[i].SerializeAsString()) << "frame " << i;
  }
  EXPECT_TRUE(SplitFrameChunk("", split));
  EXPECT_EQ(split.size(), frames.size());
}

TEST(FrameChunksTest, SplitReportsDamage) {
  const std::string data = EncodeFrameChunks(MakeFrames(3, 2))[0].data;
  const std::string_view whole(data);
  std::vector<std::string_view> split;
  EXPECT_FALSE(SplitFrameChunk(whole.substr(0, whole.size() - 3), split));  // truncated
  EXPECT_EQ(split.size(), 2u);  // the frames before the damage
  std::string bad_tag = data;
  bad_tag[1] = 0x07;  // the first frame's first tag: field 0, wire type 7
  split.clear();
  EXPECT_FALSE(SplitFrameChunk(bad_tag, split));
  EXPECT_TRUE(split.empty());
  std::string long_field = data;
  long_field[0] = static_cast<char>(long_field[0] - 1);  // the first frame ends inside a field
  EXPECT_FALSE(SplitFrameChunk(long_field, split));
}

TEST_P(StoreFramesTest, SerializedFramesAsStored) {
  auto store = Open();
  const std::vector<v1::Frame> frames = MakeFrames(kFramesPerChunk + 7, 6);
  store->FinishRun(MakeRun("r-1", v1::FINISHED, 1000), frames);
  std::string data;
  std::vector<std::string_view> split;
  std::size_t checked = 0;
  for (std::optional<int64_t> next = 0; next;) {
    split.clear();
    next = store->GetSerializedFrames("r-1", *next, data, split);
    for (std::string_view bytes : split) {
      ASSERT_LT(checked, frames.size());
      EXPECT_EQ(bytes, frames[checked].SerializeAsString()) << "frame " << checked;
      ++checked;
    }
  }
  EXPECT_EQ(checked, frames.size());
  EXPECT_FALSE(store->GetSerializedFrames("r-missing", 0, data, split).has_value());
}

TEST_P(StoreFramesTest, RoundTripAcrossSeveralChunks) {
  auto store = Open();
  const std::vector<v1::Frame> frames = MakeFrames(3 * kFramesPerChunk + 17, 6);
  const v1::RunInfo run = MakeRun("r-1", v1::FINISHED, 1000);
  store->FinishRun(run, frames);
  EXPECT_TRUE(Same(*store->GetRun("r-1"), run));
  ExpectSameFrames(store->GetFrames("r-1"), frames);
}

TEST_P(StoreFramesTest, NoFramesAndUnknownRun) {
  auto store = Open();
  store->FinishRun(MakeRun("r-empty", v1::FAILED, 1000), {});
  EXPECT_EQ(store->GetRun("r-empty")->state(), v1::FAILED);
  EXPECT_TRUE(store->GetFrames("r-empty").empty());
  EXPECT_TRUE(store->GetFrames("r-missing").empty());
}

TEST_P(StoreFramesTest, FinishRunAgainReplacesFrames) {
  auto store = Open();
  store->FinishRun(MakeRun("r-1", v1::FINISHED, 1000), MakeFrames(kFramesPerChunk + 5, 2));
  const std::vector<v1::Frame> fewer = MakeFrames(3, 2);
  store->FinishRun(MakeRun("r-1", v1::FINISHED, 1000), fewer);
  ExpectSameFrames(store->GetFrames("r-1"), fewer);
}

// A running run's frames go in chunk by chunk; the last chunk comes with the final info.
// Readers see the stored chunks of the running run, then every frame once it ended.
TEST_P(StoreFramesTest, ChunksWrittenDuringTheRunThenFinished) {
  auto store = Open();
  store->PutRun(MakeRun("r-1", v1::RUNNING, 1000));
  const std::vector<v1::Frame> frames = MakeFrames(2 * kFramesPerChunk + 5, 6);
  FrameChunkBuilder builder;
  int64_t index = 0;
  for (const v1::Frame& frame : frames) {
    builder.Add(frame);
    if (builder.frame_count() == static_cast<int64_t>(kFramesPerChunk)) {
      store->PutFrameChunk("r-1", index++, builder.Take(), "");
    }
  }
  EXPECT_EQ(store->GetRun("r-1")->state(), v1::RUNNING);
  EXPECT_EQ(store->GetFrames("r-1").size(), 2 * kFramesPerChunk);  // visible while it runs

  const v1::RunInfo finished = MakeRun("r-1", v1::FINISHED, 1000);
  EXPECT_TRUE(store->FinishRun(finished, index, builder.Take(), ""));
  EXPECT_TRUE(builder.empty());
  EXPECT_TRUE(Same(*store->GetRun("r-1"), finished));
  ExpectSameFrames(store->GetFrames("r-1"), frames);

  // Read back one chunk at a time.
  std::vector<v1::Frame> read;
  std::vector<std::size_t> sizes;
  for (std::optional<int64_t> next = 0; next;) {
    const std::size_t before = read.size();
    next = store->GetFrameChunk("r-1", *next, read);
    if (next) sizes.push_back(read.size() - before);
  }
  EXPECT_THAT(sizes, ::testing::ElementsAre(kFramesPerChunk, kFramesPerChunk, 5u));
  ExpectSameFrames(read, frames);
}

TEST_P(StoreFramesTest, FinishRunWithAnEmptyLastChunkDropsStaleChunks) {
  auto store = Open();
  store->PutRun(MakeRun("r-1", v1::RUNNING, 1000));
  const std::vector<EncodedFrameChunk> chunks = EncodeFrameChunks(MakeFrames(12, 2), 4);
  for (int i = 0; i < 3; ++i) store->PutFrameChunk("r-1", i, chunks[i], "");
  // Finished after two chunks (e.g. a chunk 2 left by an earlier attempt): chunk 2 goes.
  EXPECT_TRUE(store->FinishRun(MakeRun("r-1", v1::CANCELLED, 1000), 2, EncodedFrameChunk(), ""));
  EXPECT_EQ(store->GetRun("r-1")->state(), v1::CANCELLED);
  const std::vector<v1::Frame> frames = store->GetFrames("r-1");
  ASSERT_EQ(frames.size(), 8u);
  EXPECT_EQ(frames.back().seq(), 7);
  std::vector<v1::Frame> none;
  EXPECT_FALSE(store->GetFrameChunk("r-missing", 0, none).has_value());
  EXPECT_TRUE(none.empty());
}

// A trigger added through a second connection makes the second chunk's insert fail: the
// transaction must roll back the run row and the first chunk, and the error must say what
// failed and why.
TEST(StoreFramesSqliteTest, FinishRunIsAtomic) {
  TempDirectory temp;
  auto store = Store::Open(temp.str());
  const v1::RunInfo running = MakeRun("r-1", v1::RUNNING, 1000);
  store->PutRun(running);
  auto other = SqliteConnection::Open(store->path());
  other.Exec(
      "CREATE TRIGGER fail_second_chunk BEFORE INSERT ON frame_chunks WHEN NEW.chunk >= 1 "
      "BEGIN SELECT RAISE(ABORT, 'injected disk failure'); END",
      "add failing trigger");

  try {
    store->FinishRun(MakeRun("r-1", v1::FINISHED, 1000), MakeFrames(kFramesPerChunk + 1, 6));
    FAIL() << "FinishRun did not throw";
  } catch (const InternalError& error) {
    EXPECT_THAT(error.what(), HasSubstr("insert frames failed: injected disk failure"));
  }
  EXPECT_TRUE(Same(*store->GetRun("r-1"), running));  // the previous row
  EXPECT_TRUE(store->GetFrames("r-1").empty());
  SqliteStatement count(other, "SELECT count(*) FROM frame_chunks", "count chunks");
  ASSERT_TRUE(count.Step());
  EXPECT_EQ(count.ColumnInt64(0), 0);  // nothing partial visible to another reader
  count.Reset();

  // The store stays usable after the failure.
  other.Exec("DROP TRIGGER fail_second_chunk", "drop trigger");
  const std::vector<v1::Frame> frames = MakeFrames(kFramesPerChunk + 1, 6);
  store->FinishRun(MakeRun("r-1", v1::FINISHED, 1000), frames);
  EXPECT_EQ(store->GetRun("r-1")->state(), v1::FINISHED);
  ExpectSameFrames(store->GetFrames("r-1"), frames);
}

// Since schema version 5 the frames are in mbstream.frames beside the database, the row
// only points at them; bytes that do not match their checksum (a machine that stopped before
// the file reached the disk) are reported, never served.
TEST(StoreFramesSqliteTest, FramesLiveInTheFramesFileAndDamagedOnesAreReported) {
  TempDirectory temp;
  auto store = Store::Open(temp.str());
  const std::vector<v1::Frame> frames = MakeFrames(50, 6);
  store->FinishRun(MakeRun("r-1", v1::FINISHED, 1000), frames);
  ExpectSameFrames(store->GetFrames("r-1"), frames);

  const std::filesystem::path file = temp.path() / Store::kFramesFileName;
  const std::string chunk = EncodeFrameChunks(frames).front().data;
  EXPECT_EQ(std::filesystem::file_size(file), chunk.size());
  auto raw = SqliteConnection::Open(store->path());
  SqliteStatement row(raw, "SELECT length(data), file_offset, file_bytes FROM frame_chunks",
                      "read chunk row");
  ASSERT_TRUE(row.Step());
  EXPECT_EQ(row.ColumnInt64(0), 0);  // nothing in the row
  EXPECT_EQ(row.ColumnInt64(1), 0);
  EXPECT_EQ(static_cast<std::size_t>(row.ColumnInt64(2)), chunk.size());
  row.Reset();

  // A second run's frames follow the first's; reopening the store appends after both.
  store->FinishRun(MakeRun("r-2", v1::FINISHED, 1001), frames);
  store.reset();
  store = Store::Open(temp.str());
  store->FinishRun(MakeRun("r-3", v1::FINISHED, 1002), frames);
  EXPECT_EQ(std::filesystem::file_size(file), 3 * chunk.size());
  for (const char* id : {"r-1", "r-2", "r-3"}) ExpectSameFrames(store->GetFrames(id), frames);

  {  // one byte of r-2's frames changed on disk
    std::FILE* f = std::fopen(file.c_str(), "r+b");
    ASSERT_NE(f, nullptr);
    std::fseek(f, static_cast<long>(chunk.size() + 10), SEEK_SET);
    const int byte = std::fgetc(f);
    std::fseek(f, static_cast<long>(chunk.size() + 10), SEEK_SET);
    std::fputc(byte ^ 0x40, f);
    std::fclose(f);
  }
  try {
    store->GetFrames("r-2");
    FAIL() << "damaged frames were served";
  } catch (const InternalError& error) {
    EXPECT_THAT(error.what(), HasSubstr("the frames of run r-2 (chunk 0"));
    EXPECT_THAT(error.what(), HasSubstr("missing or damaged"));
  }
  ExpectSameFrames(store->GetFrames("r-1"), frames);                        // the others are intact
  std::filesystem::resize_file(file, 2 * chunk.size() + chunk.size() / 2);  // r-3 cut short
  EXPECT_THROW(store->GetFrames("r-3"), InternalError);
}

TEST(StoreFramesSqliteTest, FramesStoredInTheRowBeforeVersionFiveAreStillRead) {
  TempDirectory temp;
  const std::vector<v1::Frame> frames = MakeFrames(30, 6);
  {
    auto store = Store::Open(temp.str());
    store->PutRun(MakeRun("r-1", v1::FINISHED, 1000));
  }
  {  // what a version-4 server left: the frames in frame_chunks.data
    auto raw = SqliteConnection::Open((temp.path() / Store::kFileName).string());
    raw.Exec(std::string(kDropFrameFileColumns) + "PRAGMA user_version = 4",
             "make a version-4 store");
    SqliteStatement insert(raw,
                           "INSERT INTO frame_chunks (run_id, chunk, first_seq, frame_count, data) "
                           "VALUES ('r-1', 0, 0, 30, ?1)",
                           "insert a version-4 chunk");
    const std::string data = EncodeFrameChunks(frames).front().data;
    insert.BindBlob(1, data);
    insert.Run();
    insert.Reset();
  }
  auto store = Store::Open(temp.str());
  ExpectSameFrames(store->GetFrames("r-1"), frames);
  store->FinishRun(MakeRun("r-2", v1::FINISHED, 1001), frames);  // new ones go to the file
  ExpectSameFrames(store->GetFrames("r-2"), frames);
  EXPECT_GT(std::filesystem::file_size(temp.path() / Store::kFramesFileName), 0u);
}

// The big case of the brief, measured once: run with --gtest_also_run_disabled_tests.
// MBSTREAM_STORE_BIG_FRAMES overrides the frame count (default 1,000,000).
TEST(StoreFramesSqliteTest, DISABLED_MillionFramesOfSixJoints) {
  const char* override_count = std::getenv("MBSTREAM_STORE_BIG_FRAMES");
  const int64_t count = override_count != nullptr ? std::atoll(override_count) : 1'000'000;
  TempDirectory temp;
  auto store = Store::Open(temp.str());
  const std::vector<v1::Frame> frames = MakeFrames(count, 6);
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  store->FinishRun(MakeRun("r-big", v1::FINISHED, 1000), frames);
  const auto t1 = Clock::now();
  const std::vector<v1::Frame> loaded = store->GetFrames("r-big");
  const auto t2 = Clock::now();
  const double finish_s = std::chrono::duration<double>(t1 - t0).count();
  const double get_s = std::chrono::duration<double>(t2 - t1).count();
  std::printf("%lld frames x 6 joints: FinishRun %.3f s, GetFrames %.3f s, file %.1f MB\n",
              static_cast<long long>(count), finish_s, get_s,
              static_cast<double>(std::filesystem::file_size(store->path())) / 1e6);
  ASSERT_EQ(loaded.size(), frames.size());
  EXPECT_TRUE(Same(loaded.front(), frames.front()));
  EXPECT_TRUE(Same(loaded[loaded.size() / 2], frames[frames.size() / 2]));
  EXPECT_TRUE(Same(loaded.back(), frames.back()));
}

}  // namespace
}  // namespace mbstream

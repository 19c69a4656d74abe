// SqliteStore::Backup: a copy taken while runs are written and deleted opens as a store in which
// every run is whole (each chunk's length and CRC-32C checked as it is read), as of one moment.
#include <atomic>
#include <filesystem>
#include <fstream>
#include <thread>

#include <gmock/gmock.h>

#include "server/store/frame_chunks.h"
#include "server/store/store.h"
#include "shared/common/check.h"
#include "tests/server/store/store_test_util.h"

namespace mbstream::testing {
namespace {

using ::testing::HasSubstr;

void StoreRun(Store& store, const std::string& id, int64_t frames) {
  store.PutRun(MakeRun(id, v1::RUNNING, 1));
  v1::RunInfo ended = MakeRun(id, v1::FINISHED, 1);
  ended.set_frames(frames);
  store.FinishRun(ended, MakeFrames(frames, 6));
}

// Every run of `store` read whole: an ended run has the frames its row counts; a run still
// running when the copy was taken has the chunks stored until then. GetFrames throws on a chunk
// whose bytes do not match its CRC.
void ExpectEveryRunWhole(const Store& store) {
  for (const v1::RunInfo& run : store.ListRuns()) {
    SCOPED_TRACE(run.id());
    std::vector<v1::Frame> frames;
    ASSERT_NO_THROW(frames = store.GetFrames(run.id()));
    if (run.state() == v1::FINISHED) {
      EXPECT_EQ(static_cast<int64_t>(frames.size()), run.frames());
    }
    for (size_t i = 0; i < frames.size(); ++i) ASSERT_EQ(frames[i].seq(), static_cast<int64_t>(i));
  }
}

TEST(StoreBackupTest, ACopyTakenWhileRunsAreWrittenAndDeletedHasEveryRunWhole) {
  TempDirectory source, backups;
  std::unique_ptr<Store> store = Store::Open(source.str());
  constexpr int kOld = 8;
  for (int i = 0; i < kOld; ++i) StoreRun(*store, "r-" + std::to_string(i), 2 * kFramesPerChunk);

  std::atomic<bool> stop{false};
  std::atomic<int> written{0};
  std::thread writer([&] {  // runs written chunk by chunk, as a running run's spool does
    const std::vector<EncodedFrameChunk> chunks = EncodeFrameChunks(MakeFrames(600, 6), 200);
    for (int i = 0; !stop; ++i) {
      const std::string id = "w-" + std::to_string(i);
      store->PutRun(MakeRun(id, v1::RUNNING, 2));
      for (size_t c = 0; c + 1 < chunks.size(); ++c)
        store->PutFrameChunk(id, static_cast<int64_t>(c), chunks[c], "");
      v1::RunInfo ended = MakeRun(id, v1::FINISHED, 2);
      ended.set_frames(600);
      store->FinishRun(ended, static_cast<int64_t>(chunks.size() - 1), chunks.back(), "");
      ++written;
    }
  });
  while (written == 0) std::this_thread::yield();  // a run being written at every copy

  std::vector<StoreBackup> copies;
  for (int b = 0; b < 4; ++b) {
    std::thread deleter([&, b] {  // deleted while the copy is taken: released only after it
      ASSERT_TRUE(store->DeleteRun("r-" + std::to_string(2 * b)));
      ASSERT_TRUE(store->DeleteRun("r-" + std::to_string(2 * b + 1)));
    });
    copies.push_back(store->Backup((backups.path() / std::to_string(b)).string()));
    deleter.join();
  }
  stop = true;
  writer.join();
  EXPECT_NO_THROW(ExpectEveryRunWhole(*store));
  store.reset();

  for (const StoreBackup& copy : copies) {
    SCOPED_TRACE(copy.dir);
    EXPECT_EQ(std::filesystem::file_size(std::filesystem::path(copy.dir) / Store::kFramesFileName),
              static_cast<uint64_t>(copy.frames_bytes));
    std::unique_ptr<Store> restored = Store::Open(copy.dir);
    EXPECT_EQ(static_cast<int64_t>(restored->ListRuns().size()), copy.runs);
    ExpectEveryRunWhole(*restored);
  }
}

TEST(StoreBackupTest, ABackupNeverWritesOverAnything) {
  TempDirectory source, target;
  std::unique_ptr<Store> store = Store::Open(source.str());
  StoreRun(*store, "r-1", 5);
  std::filesystem::create_directories(target.path());
  std::ofstream(target.path() / "notes.txt") << "an operator's file";
  try {
    store->Backup(target.str());
    FAIL() << "a backup into a directory that holds a file";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("not empty"));
    EXPECT_THAT(error.what(), HasSubstr(target.str()));
  }
  const StoreBackup copy = store->Backup((target.path() / "copy").string());
  EXPECT_EQ(copy.runs, 1);
  EXPECT_EQ(Store::Open(copy.dir)->GetFrames("r-1").size(), 5u);
  EXPECT_THROW(store->Backup(copy.dir), InputError);  // the copy is not empty any more
}

}  // namespace
}  // namespace mbstream::testing

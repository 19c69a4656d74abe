// The SQLite store gives space back: the frames file's blocks of deleted runs (holes punched,
// frame_file.h), SQLite's free pages (incremental vacuum, also on a store made before it), and
// a kill -9 at random points of deletions and their releases leaves every remaining run whole
// with valid CRCs.
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <random>
#include <set>

#include <gmock/gmock.h>

#include "server/store/frame_chunks.h"
#include "server/store/sqlite_connection.h"
#include "server/store/sqlite_statement.h"
#include "server/store/store.h"
#include "tests/server/store/store_test_util.h"

namespace mbstream::testing {
namespace {

// Bytes the file occupies on its disk.
int64_t Allocated(const std::filesystem::path& file) {
  struct stat status {};
  return ::stat(file.c_str(), &status) == 0 ? static_cast<int64_t>(status.st_blocks) * 512 : -1;
}

// Whether the file system of `directory` punches holes (tmpfs, ext4, xfs, btrfs do).
bool PunchesHoles(const std::filesystem::path& directory) {
  const std::string probe = (directory / "punch-probe").string();
  const int fd = ::open(probe.c_str(), O_RDWR | O_CREAT | O_TRUNC, 0600);
  const std::string block(1 << 16, 'x');
  const bool written = fd >= 0 && ::write(fd, block.data(), block.size()) == 1 << 16;
  const bool punched =
      written && ::fallocate(fd, FALLOC_FL_PUNCH_HOLE | FALLOC_FL_KEEP_SIZE, 0, 1 << 16) == 0;
  if (fd >= 0) ::close(fd);
  std::filesystem::remove(probe);
  return punched;
}

void StoreRun(Store& store, const std::string& id, int64_t frames, int dofs) {
  store.PutRun(MakeRun(id, v1::RUNNING, 1));
  store.FinishRun(MakeRun(id, v1::FINISHED, 1), MakeFrames(frames, dofs));
}

TEST(FrameReclaimTest, TheBlocksOfDeletedRunsGoBackToTheDisk) {
  TempDirectory temp;
  std::unique_ptr<Store> store = Store::Open(temp.str());
  if (!PunchesHoles(temp.path())) GTEST_SKIP() << "the temp file system cannot punch holes";
  const std::filesystem::path frames = temp.path() / Store::kFramesFileName;
  for (int i = 0; i < 4; ++i) StoreRun(*store, "r-" + std::to_string(i), 3 * kFramesPerChunk, 6);
  const int64_t full = Allocated(frames);
  ASSERT_GT(full, 4 << 20);  // about 2.5 MB a run

  for (int i = 0; i < 3; ++i) ASSERT_TRUE(store->DeleteRun("r-" + std::to_string(i)));
  const int64_t after = Allocated(frames);
  EXPECT_LT(after, full / 4 + (64 << 10)) << "from " << full << " bytes";
  EXPECT_EQ(store->GetFrames("r-3").size(), 3 * kFramesPerChunk);  // the rest untouched

  // A run stored again leaves its first frames' bytes unreferenced: released at the next open.
  StoreRun(*store, "r-3", 3 * kFramesPerChunk, 6);
  const int64_t replaced = Allocated(frames);
  EXPECT_GT(replaced, after + (2 << 20));
  store.reset();
  store = Store::Open(temp.str());
  EXPECT_LT(Allocated(frames), replaced - (2 << 20));
  EXPECT_EQ(store->GetFrames("r-3").size(), 3 * kFramesPerChunk);
}

int64_t AutoVacuum(const std::string& database) {
  SqliteConnection connection = SqliteConnection::Open(database);
  SqliteStatement mode(connection, "PRAGMA auto_vacuum", "read");
  return mode.Step() ? mode.ColumnInt64(0) : -1;
}

TEST(FrameReclaimTest, SqliteFreePagesAreReturnedAlsoByAStoreMadeBeforeIncrementalVacuum) {
  TempDirectory temp;
  const std::string database = (temp.path() / Store::kFileName).string();
  Store::Open(temp.str()).reset();
  EXPECT_EQ(AutoVacuum(database), 2);  // INCREMENTAL from the start
  {
    SqliteConnection connection = SqliteConnection::Open(database);  // as before this version
    connection.Exec("PRAGMA auto_vacuum = NONE", "test");
    connection.Exec("VACUUM", "test");
  }
  ASSERT_EQ(AutoVacuum(database), 0);
  std::unique_ptr<Store> store = Store::Open(temp.str());  // converted once
  EXPECT_EQ(AutoVacuum(database), 2);
  // Probe reports fill pages of the database itself; deleting their run frees them.
  std::vector<v1::ProbeReport> probes;
  for (int seq = 0; seq < 20000; ++seq) probes.push_back(MakeProbe("r-1", seq, "tcp"));
  StoreRun(*store, "r-1", 10, 2);
  store->AddProbes(probes);
  store.reset();  // checkpointed into the database file
  store = Store::Open(temp.str());
  const int64_t full = Allocated(database);
  ASSERT_TRUE(store->DeleteRun("r-1"));
  store.reset();
  EXPECT_LT(Allocated(database), full / 2) << "from " << full << " bytes";
}

// A child process deletes runs (and stores some again) while the parent kills it with
// SIGKILL after a random number of them has begun; then every run still listed must read
// back whole, each chunk's CRC checked.
TEST(FrameReclaimTest, KillNineAtRandomPointsLeavesEveryRemainingRunWhole) {
  TempDirectory temp;
  constexpr int kRounds = 12, kRunsPerRound = 8;
  constexpr int64_t kFrames = kFramesPerChunk + 777;
  std::mt19937 random(35);
  int next_id = 0;
  for (int round = 0; round < kRounds; ++round) {
    SCOPED_TRACE("round " + std::to_string(round));
    std::vector<std::string> ids;
    {
      std::unique_ptr<Store> store = Store::Open(temp.str());
      for (int i = 0; i < kRunsPerRound; ++i) {
        ids.push_back("r-" + std::to_string(next_id++));
        StoreRun(*store, ids.back(), kFrames, 2);
      }
      for (const v1::RunInfo& run : store->ListRuns()) {
        if (std::find(ids.begin(), ids.end(), run.id()) == ids.end()) ids.push_back(run.id());
      }
    }  // closed before the fork: the child is the only one to use it
    std::shuffle(ids.begin(), ids.end(), random);
    int progress[2];
    ASSERT_EQ(::pipe(progress), 0);
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      ::close(progress[0]);
      std::unique_ptr<Store> store = Store::Open(temp.str());  // releases gaps at open
      for (size_t i = 0; i < ids.size(); ++i) {
        if (::write(progress[1], "x", 1) != 1) ::_exit(2);
        if (i % 3 == 2) {
          StoreRun(*store, ids[i], kFrames, 2);  // stored again: its old bytes a gap
        } else {
          store->DeleteRun(ids[i]);
        }
      }
      ::_exit(0);
    }
    ::close(progress[1]);
    const int begun = std::uniform_int_distribution<int>(1, static_cast<int>(ids.size()))(random);
    char byte;
    for (int i = 0; i < begun && ::read(progress[0], &byte, 1) == 1; ++i) {
    }
    ::kill(child, SIGKILL);
    int status = 0;
    ::waitpid(child, &status, 0);
    ::close(progress[0]);

    std::unique_ptr<Store> store = Store::Open(temp.str());
    for (const v1::RunInfo& run : store->ListRuns()) {
      std::vector<v1::Frame> frames;
      EXPECT_NO_THROW(frames = store->GetFrames(run.id())) << run.id();
      EXPECT_EQ(frames.size(), static_cast<size_t>(kFrames)) << run.id();
    }
  }
}

}  // namespace
}  // namespace mbstream::testing

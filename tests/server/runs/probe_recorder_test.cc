// ProbeRecorder: reports go to the store in batches as they come (a full batch, or a partial
// one once the interval of the manual clock has passed), the last batch on Flush; a lost
// lease or a store failure stops it; reports from many threads are each stored once.
#include "server/runs/probe_recorder.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "server/store/store.h"
#include "tests/server/runs/manual_run_clock.h"

namespace mbstream {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;

std::vector<v1::ProbeReport> Reports(const std::string& run_id, int64_t first_seq, int count) {
  std::vector<v1::ProbeReport> reports(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    reports[i].set_run_id(run_id);
    reports[i].set_seq(first_seq + i);
    reports[i].set_probe("tcp");
    reports[i].mutable_position_m()->set_x(0.01 * static_cast<double>(first_seq + i));
  }
  return reports;
}

// A writer that keeps each batch's frame numbers.
struct Batches {
  std::vector<std::vector<int64_t>> seqs;
  ProbeRecorder::BatchWriter Writer() {
    return [this](const std::vector<v1::ProbeReport>& batch) {
      std::vector<int64_t>& seq = seqs.emplace_back();
      for (const v1::ProbeReport& report : batch) seq.push_back(report.seq());
      return true;
    };
  }
};

ProbeRecorder::Options Options(std::size_t batch_reports, milliseconds interval = {},
                               int64_t max_reports = 1000) {
  ProbeRecorder::Options options;
  options.batch_reports = batch_reports;
  options.interval = interval;
  options.max_reports = max_reports;
  return options;
}

TEST(ProbeRecorderTest, StoresEachFullBatchAsItFillsAndTheRestOnFlush) {
  testing::ManualRunClock clock;
  ProbeRecorder recorder("run r-1", clock, Options(3));
  Batches batches;
  recorder.Open(batches.Writer());
  for (int64_t seq = 0; seq < 7; ++seq) {
    ASSERT_TRUE(recorder.Add(Reports("r-1", seq, 1)));
    EXPECT_EQ(recorder.FlushIfDue(), seq == 2 || seq == 5) << "seq " << seq;
  }
  EXPECT_EQ(recorder.stored(), 6);
  EXPECT_EQ(recorder.accepted(), 7);
  ASSERT_TRUE(recorder.Flush());
  EXPECT_EQ(batches.seqs, (std::vector<std::vector<int64_t>>{{0, 1, 2}, {3, 4, 5}, {6}}));
  EXPECT_EQ(recorder.stored(), 7);
  EXPECT_EQ(recorder.batches(), 3);
  EXPECT_TRUE(recorder.Flush());  // nothing left: no empty batch
  EXPECT_EQ(batches.seqs.size(), 3u);
}

TEST(ProbeRecorderTest, StoresAPartialBatchOnceTheIntervalHasPassedSinceTheLast) {
  testing::ManualRunClock clock;
  ProbeRecorder recorder("run r-1", clock, Options(512, milliseconds(1000)));
  Batches batches;
  recorder.Open(batches.Writer());  // the interval runs from here
  ASSERT_TRUE(recorder.Add(Reports("r-1", 0, 2)));
  EXPECT_FALSE(recorder.FlushIfDue());
  clock.Advance(milliseconds(999));
  EXPECT_FALSE(recorder.FlushIfDue());
  clock.Advance(milliseconds(1));
  EXPECT_TRUE(recorder.FlushIfDue());
  EXPECT_EQ(batches.seqs, (std::vector<std::vector<int64_t>>{{0, 1}}));
  // The next interval runs from that batch; nothing at hand: nothing stored.
  clock.Advance(milliseconds(1500));
  EXPECT_FALSE(recorder.FlushIfDue());
  ASSERT_TRUE(recorder.Add(Reports("r-1", 2, 1)));
  EXPECT_TRUE(recorder.FlushIfDue());  // 1.5 s since the last batch
  EXPECT_EQ(recorder.stored(), 3);
}

TEST(ProbeRecorderTest, KeepsReportsAddedBeforeOpenForTheFirstBatch) {
  testing::ManualRunClock clock;
  ProbeRecorder recorder("run r-1", clock, Options(2));
  ASSERT_TRUE(recorder.Add(Reports("r-1", 0, 3)));
  EXPECT_FALSE(recorder.FlushIfDue());  // no writer yet
  Batches batches;
  recorder.Open(batches.Writer());
  EXPECT_TRUE(recorder.FlushIfDue());
  EXPECT_EQ(batches.seqs, (std::vector<std::vector<int64_t>>{{0, 1, 2}}));
}

TEST(ProbeRecorderTest, RefusesReportsAfterCloseAndBeyondItsLimit) {
  testing::ManualRunClock clock;
  ProbeRecorder recorder("run r-1", clock, Options(512, {}, 4));
  Batches batches;
  recorder.Open(batches.Writer());
  EXPECT_TRUE(recorder.Add(Reports("r-1", 0, 3)));
  EXPECT_FALSE(recorder.Add(Reports("r-1", 3, 2)));  // 5 > 4: none of them kept
  EXPECT_TRUE(recorder.Add(Reports("r-1", 3, 1)));
  recorder.Close();
  EXPECT_FALSE(recorder.Add(Reports("r-1", 4, 1)));
  EXPECT_TRUE(recorder.Flush());  // the reports kept before Close are stored
  EXPECT_EQ(batches.seqs, (std::vector<std::vector<int64_t>>{{0, 1, 2, 3}}));
}

TEST(ProbeRecorderTest, ALostLeaseStoresNothingMoreAndRefusesLaterReports) {
  testing::ManualRunClock clock;
  ProbeRecorder recorder("run r-1", clock, Options(2));
  int calls = 0;
  recorder.Open([&](const std::vector<v1::ProbeReport>&) { return ++calls == 1; });
  ASSERT_TRUE(recorder.Add(Reports("r-1", 0, 2)));
  EXPECT_TRUE(recorder.FlushIfDue());
  ASSERT_TRUE(recorder.Add(Reports("r-1", 2, 2)));
  EXPECT_FALSE(recorder.FlushIfDue());  // the writer's lease is gone
  EXPECT_TRUE(recorder.lease_lost());
  EXPECT_FALSE(recorder.Add(Reports("r-1", 4, 1)));
  EXPECT_FALSE(recorder.Flush());
  EXPECT_EQ(calls, 2);
  EXPECT_EQ(recorder.stored(), 2);
}

TEST(ProbeRecorderTest, AStoreFailureIsKeptAsItsErrorAndLaterReportsAreRefused) {
  testing::ManualRunClock clock;
  ProbeRecorder recorder("run r-1", clock, Options(1));
  recorder.Open([](const std::vector<v1::ProbeReport>&) -> bool {
    throw std::runtime_error("store probe reports: database or disk is full");
  });
  ASSERT_TRUE(recorder.Add(Reports("r-1", 0, 1)));
  EXPECT_FALSE(recorder.FlushIfDue());  // does not throw
  EXPECT_EQ(recorder.error(), "store probe reports: database or disk is full");
  EXPECT_FALSE(recorder.Add(Reports("r-1", 1, 1)));
  EXPECT_TRUE(recorder.Flush());  // nothing more is written
}

// Through the store's own call (Store::AddProbes): the reports of a batch can be read back
// before the run ends, as after a crash.
TEST(ProbeRecorderTest, BatchesReachTheStoreBeforeTheLastFlush) {
  const fs::path dir =
      fs::temp_directory_path() / ("mbstream-probe-recorder-" + std::to_string(getpid()));
  fs::remove_all(dir);
  {
    auto store = Store::Open(dir.string());
    v1::RunInfo info;
    info.set_id("r-1");
    store->PutRun(info);
    testing::ManualRunClock clock;
    ProbeRecorder recorder("run r-1", clock, Options(512, milliseconds(1000)));
    recorder.Open([&](const std::vector<v1::ProbeReport>& batch) {
      store->AddProbes(batch);
      return true;
    });
    ASSERT_TRUE(recorder.Add(Reports("r-1", 0, 5)));
    clock.Advance(milliseconds(1000));
    ASSERT_TRUE(recorder.FlushIfDue());
    ASSERT_TRUE(recorder.Add(Reports("r-1", 5, 2)));
    const std::vector<v1::ProbeReport> kept = store->GetProbes("r-1");
    ASSERT_EQ(kept.size(), 5u);
    EXPECT_EQ(kept[4].seq(), 4);
    EXPECT_DOUBLE_EQ(kept[4].position_m().x(), 0.04);
    ASSERT_TRUE(recorder.Flush());
    EXPECT_EQ(store->GetProbes("r-1").size(), 7u);
  }
  fs::remove_all(dir);
}

// Readers add and store due batches (as a replay's reader does) while another thread stores
// batches too (as a run's worker does): every report is stored exactly once, in the order
// each reader added its own. Halfway, each reader waits for a stored batch, so that reports
// are added after one whatever the threads' scheduling (one batch of all 1,200 happened on a
// busy machine).
TEST(ProbeRecorderTest, ReportsAddedWhileBatchesAreStoredAreEachStoredOnce) {
  testing::ManualRunClock clock;
  ProbeRecorder recorder("run r-1", clock, Options(7, {}, 1'000'000));
  Batches batches;
  recorder.Open(batches.Writer());
  constexpr int kReaders = 3, kEach = 400;
  std::atomic<int> readers_done{0};
  std::vector<std::thread> readers;
  for (int r = 0; r < kReaders; ++r) {
    readers.emplace_back([&, r] {
      for (int i = 0; i < kEach; ++i) {
        if (i == kEach / 2) {
          while (recorder.batches() == 0) std::this_thread::yield();  // the worker stores one
        }
        EXPECT_TRUE(recorder.Add(Reports("r-1", int64_t{r} * kEach + i, 1)));
        recorder.FlushIfDue();
      }
      ++readers_done;
    });
  }
  std::thread worker([&] {
    while (readers_done < kReaders) recorder.FlushIfDue();
  });
  for (std::thread& reader : readers) reader.join();
  worker.join();
  ASSERT_TRUE(recorder.Flush());
  std::vector<int64_t> last(kReaders, -1);
  int64_t total = 0;
  for (const std::vector<int64_t>& batch : batches.seqs) {
    for (int64_t seq : batch) {
      const int64_t reader = seq / kEach;
      EXPECT_GT(seq, last[reader]);
      last[reader] = seq;
      ++total;
    }
  }
  EXPECT_EQ(total, kReaders * kEach);
  EXPECT_EQ(recorder.stored(), kReaders * kEach);
  EXPECT_GT(recorder.batches(), 1);
}

}  // namespace
}  // namespace mbstream

// RunManager without gRPC, paced by a manual clock: a realtime run sends each frame when its
// wall time comes, not before; cancel and shutdown end a waiting run at once; a private
// store's claims are made in memory; a subscriber of a run claimed here and not yet prepared
// waits for it.
#include "server/runs/run_manager.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <thread>

#include <unistd.h>

#include "server/runs/request_error.h"
#include "server/store/frame_chunks.h"
#include "server/store/run_lease.h"
#include "server/store/store.h"
#include "server/wire/stats_conversion.h"
#include "tests/server/runs/manual_run_clock.h"

namespace mbstream {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;
using std::chrono::nanoseconds;

class RunManagerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mbstream-run-manager-" + std::to_string(getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    store_ = Store::Open(dir_.string());
    models_ = std::make_unique<ModelRegistry>(store_.get(), limits_);
    ASSERT_GT(models_->LoadBuiltins(std::string(MBSTREAM_SOURCE_DIR) + "/models"), 0);
    runs_ = std::make_unique<RunManager>(models_.get(), store_.get(), limits_, &clock_);
  }
  void TearDown() override {
    runs_.reset();
    models_.reset();
    store_.reset();
    fs::remove_all(dir_);
  }

  // The single pendulum swinging freely for `duration_s`, a frame every 0.1 s.
  static v1::RunSpec Swing(double duration_s, double realtime) {
    v1::RunSpec spec;
    spec.set_duration_s(duration_s);
    spec.set_output_interval_s(0.1);
    spec.set_realtime(realtime);
    return spec;
  }

  // Waits for the run's end event and returns its stored info.
  v1::RunInfo WaitForEnd(const std::shared_ptr<Subscription>& subscription,
                         const std::string& run_id) {
    std::deque<StreamEvent> events;
    for (;;) {
      events.clear();
      int64_t missed = 0;
      if (!subscription->Pop(std::chrono::seconds(30), 1024, &events, &missed)) break;
      for (const StreamEvent& event : events) {
        if (event.kind == StreamEvent::Kind::kRunEnded) return runs_->Get(run_id);
      }
      if (events.empty()) break;  // 30 s without an event: fail below
    }
    ADD_FAILURE() << "run " << run_id << " did not end";
    return runs_->Get(run_id);
  }

  ServerLimits limits_;
  testing::ManualRunClock clock_;
  fs::path dir_;
  std::unique_ptr<Store> store_;
  std::unique_ptr<ModelRegistry> models_;
  std::unique_ptr<RunManager> runs_;
};

TEST_F(RunManagerTest, RealtimeRunSendsEachFrameWhenItsWallTimeComes) {
  const double realtime = 2.0;  // a frame every 0.1 s of simulated time = every 50 ms of wall
  const v1::RunInfo started = runs_->Start("single_pendulum", Swing(0.5, realtime));
  const auto subscription = runs_->subscriptions().SubscribeRun(started.id(), false);
  const RunClock::TimePoint start = clock_.Now();
  for (int k = 1; k <= 5; ++k) {
    const std::optional<RunClock::TimePoint> due = clock_.WaitForWaiter();
    ASSERT_TRUE(due.has_value()) << "frame " << k;
    // Frame k (t = 0.1 k s) waits for start + 0.1 k / realtime s; frames 0..k-1 are out.
    EXPECT_NEAR(std::chrono::duration<double>(*due - start).count(), 0.1 * k / realtime, 1e-9);
    EXPECT_EQ(runs_->Get(started.id()).frames(), k);
    EXPECT_EQ(runs_->Get(started.id()).state(), v1::RUNNING);
    clock_.Advance(milliseconds(50));
  }
  const v1::RunInfo ended = WaitForEnd(subscription, started.id());
  EXPECT_EQ(ended.state(), v1::FINISHED) << ended.message();
  EXPECT_EQ(ended.frames(), 6);
  runs_->subscriptions().Unsubscribe(subscription);
}

TEST_F(RunManagerTest, CancelEndsARunWaitingForItsNextFrameAtOnce) {
  const v1::RunInfo started = runs_->Start("single_pendulum", Swing(20.0, 1.0));
  const auto subscription = runs_->subscriptions().SubscribeRun(started.id(), false);
  ASSERT_TRUE(clock_.WaitForWaiter().has_value());
  clock_.Advance(milliseconds(100));  // frame 1 goes out
  ASSERT_TRUE(clock_.WaitForWaiter().has_value());
  runs_->Cancel(started.id());  // the clock never reaches the next frame's time
  const v1::RunInfo ended = WaitForEnd(subscription, started.id());
  EXPECT_EQ(ended.state(), v1::CANCELLED);
  // Frames 0 and 1 went out on time; frame 2, computed and waiting, is kept as well.
  EXPECT_EQ(ended.frames(), 3);
  EXPECT_NE(ended.message().find("cancelled at t = 0.2"), std::string::npos) << ended.message();
  runs_->subscriptions().Unsubscribe(subscription);
}

TEST_F(RunManagerTest, ShutdownInterruptsAWaitingRunAndKeepsItsFrames) {
  const v1::RunInfo started = runs_->Start("single_pendulum", Swing(20.0, 1.0));
  ASSERT_TRUE(clock_.WaitForWaiter().has_value());
  runs_->replica().Shutdown("the test stopped the server");
  const std::optional<v1::RunInfo> stored = store_->GetRun(started.id());
  ASSERT_TRUE(stored.has_value());
  EXPECT_EQ(stored->state(), v1::INTERRUPTED);
  EXPECT_EQ(stored->frames(), 2);  // frame 0, and frame 1 that was waiting for its time
  EXPECT_NE(stored->message().find("the test stopped the server"), std::string::npos)
      << stored->message();
}

// A paced run's frames reach the store while it runs, once a second (limits_.frame_flush_s)
// of its clock has passed, not when 4,096 of them are at hand: a crash then keeps them.
TEST_F(RunManagerTest, APacedRunStoresItsFramesEverySecondOfWallTime) {
  ASSERT_EQ(limits_.frame_flush_s, 1.0);
  const v1::RunInfo started = runs_->Start("single_pendulum", Swing(20.0, 1.0));
  for (int k = 1; k <= 10; ++k) {  // frame k waits for 0.1 k s; frames 0..k-1 are out
    ASSERT_TRUE(clock_.WaitForWaiter().has_value()) << "frame " << k;
    EXPECT_TRUE(store_->GetFrames(started.id()).empty()) << "frame " << k;
    clock_.Advance(milliseconds(100));
  }
  ASSERT_TRUE(clock_.WaitForWaiter().has_value());  // frame 10 went out at 1 s, with a chunk
  EXPECT_EQ(runs_->Get(started.id()).state(), v1::RUNNING);
  EXPECT_EQ(store_->GetFrames(started.id()).size(), 11u);
  runs_->Cancel(started.id());
}

// A viewer's probe reports reach the store while the run runs, with the first frame due a
// second (limits_.frame_flush_s) of its clock after the run started: a crash then keeps them.
TEST_F(RunManagerTest, APacedRunStoresItsViewersProbesEverySecondOfWallTime) {
  const v1::RunInfo started = runs_->Start("single_pendulum", Swing(20.0, 1.0));
  const auto viewer = runs_->subscriptions().SubscribeRun(started.id(), true);
  ASSERT_TRUE(clock_.WaitForWaiter().has_value());  // frame 0 is out
  std::vector<v1::ProbeReport> report(1);
  report[0].set_run_id(started.id());
  report[0].set_seq(0);
  report[0].set_probe("tcp");
  ASSERT_TRUE(runs_->subscriptions().AddProbes(started.id(), report));
  for (int k = 1; k <= 10; ++k) {
    EXPECT_TRUE(store_->GetProbes(started.id()).empty()) << "frame " << k;
    clock_.Advance(milliseconds(100));
    ASSERT_TRUE(clock_.WaitForWaiter().has_value()) << "frame " << k;
  }
  // Frame 10 went out at 1 s, and the report's batch with it.
  EXPECT_EQ(runs_->Get(started.id()).state(), v1::RUNNING);
  EXPECT_EQ(runs_->Get(started.id()).probe_reports(), 1);
  ASSERT_EQ(store_->GetProbes(started.id()).size(), 1u);
  // For frame 11, computed and waiting for its time: kept as the run ends, its report ends
  // the end's wait for the viewer's last reports at once.
  report[0].set_seq(11);
  ASSERT_TRUE(runs_->subscriptions().AddProbes(started.id(), report));
  runs_->Cancel(started.id());
  const v1::RunInfo ended = WaitForEnd(viewer, started.id());
  EXPECT_EQ(ended.state(), v1::CANCELLED);
  EXPECT_EQ(store_->GetProbes(started.id()).size(), 2u);  // the last batch, at the end
  EXPECT_FALSE(runs_->subscriptions().AddProbes(started.id(), report));  // ended: refused
  runs_->subscriptions().Unsubscribe(viewer);
}

// AwaitChange returns with the change of state that ends the wait, not after its deadline: the
// run waits for the manual clock, which never reaches its end, and the cancel ends it.
TEST_F(RunManagerTest, AwaitChangeReturnsWhenTheRunChangesState) {
  const auto far = std::chrono::steady_clock::now() + std::chrono::hours(1);
  const v1::RunInfo started = runs_->Start("single_pendulum", Swing(20.0, 1.0));
  EXPECT_EQ(runs_->AwaitChange(started.id(), v1::QUEUED, far).state(), v1::RUNNING);
  ASSERT_TRUE(clock_.WaitForWaiter().has_value());  // running, waiting for frame 1's time
  // A deadline that has passed: the run as it is.
  EXPECT_EQ(runs_->AwaitChange(started.id(), v1::RUNNING, std::chrono::steady_clock::now()).state(),
            v1::RUNNING);
  std::thread cancel([&] { runs_->Cancel(started.id()); });
  const v1::RunInfo ended = runs_->AwaitChange(started.id(), v1::RUNNING, far);
  cancel.join();
  EXPECT_EQ(ended.state(), v1::CANCELLED) << ended.message();
  EXPECT_EQ(ended.frames(), 2);
  EXPECT_THROW(runs_->AwaitChange("nosuch", v1::QUEUED, far), RequestError);
}

// On a shared store a run is RUNNING here in the store as soon as a worker of this replica
// claimed it, before the worker has prepared it; another replica sees the claim and proxies a
// subscriber here at once. That subscriber waits for the run; it is not told the run ended
// (it used to be: started and ended at once, no frames). Here the test holds the claim, as a
// worker still preparing, and then ends the run itself.
// A private store's queue is the server's own: the claim is made in memory (the running
// run's row stays QUEUED until it ends) and a queued run cancelled is never started.
TEST_F(RunManagerTest, PrivateStoreClaimsInMemoryAndCancelsAQueuedRunBeforeAnyWorker) {
  runs_.reset();
  limits_.workers = 1;
  runs_ = std::make_unique<RunManager>(models_.get(), store_.get(), limits_, &clock_);
  const v1::RunInfo first = runs_->Start("single_pendulum", Swing(20.0, 1.0));
  ASSERT_TRUE(clock_.WaitForWaiter().has_value());  // the one worker integrates it
  const v1::RunInfo second = runs_->Start("single_pendulum", Swing(0.5, 0.0));
  EXPECT_EQ(runs_->Get(first.id()).state(), v1::RUNNING);
  EXPECT_EQ(store_->GetRun(first.id())->state(), v1::QUEUED);  // no claim transaction
  EXPECT_EQ(runs_->Get(second.id()).state(), v1::QUEUED);

  const v1::RunInfo cancelled = runs_->Cancel(second.id());
  EXPECT_EQ(cancelled.state(), v1::CANCELLED);
  EXPECT_EQ(runs_->Get(second.id()).state(), v1::CANCELLED);
  EXPECT_EQ(store_->GetRun(second.id())->state(), v1::CANCELLED);

  const auto subscription = runs_->subscriptions().SubscribeRun(first.id(), false);
  runs_->Cancel(first.id());
  const v1::RunInfo ended = WaitForEnd(subscription, first.id());
  EXPECT_EQ(ended.state(), v1::CANCELLED);
  EXPECT_EQ(store_->GetRun(first.id())->state(), v1::CANCELLED);
  EXPECT_EQ(store_->GetRun(second.id())->state(), v1::CANCELLED);  // no worker started it
  EXPECT_EQ(store_->GetRun(second.id())->frames(), 0);
  runs_->subscriptions().Unsubscribe(subscription);
}

// The result of a run that just ended is served from memory as it was stored (a sweep's
// GetResult follows every end): the store is not read for it. Without that memory, it is.
// A folder of one-file models (models/linkages) gives each its NAME.scene; a model folder
// (models/irb1600) its own scene.
TEST_F(RunManagerTest, BuiltinModelsComeWithTheirSceneScripts) {
  for (const char* name : {"irb1600", "four_bar", "slider_crank", "delta", "parallelogram"}) {
    const v1::ModelInfo info = models_->Info(name);
    EXPECT_TRUE(info.has_scene()) << name;
  }
}

TEST_F(RunManagerTest, AnEndedRunsResultAndInfoAreServedFromMemoryAsStored) {
  auto result = [&](const std::string& run_id) {
    std::string data;
    std::vector<std::string_view> views;
    std::vector<std::string> frames;
    for (std::optional<int64_t> next = 0; next;) {
      next = runs_->results().Frames(run_id, *next, data, views);
      for (std::string_view view : views) frames.emplace_back(view);
      views.clear();
    }
    return frames;
  };
  const auto far = std::chrono::steady_clock::now() + std::chrono::hours(1);
  for (const int64_t kept_bytes : {int64_t{16} << 20, int64_t{0}}) {
    runs_.reset();
    limits_.recent_results_bytes = kept_bytes;
    runs_ = std::make_unique<RunManager>(models_.get(), store_.get(), limits_, &clock_);
    const v1::RunInfo started = runs_->Start("single_pendulum", Swing(1.0, 0.0));
    v1::RunInfo info = runs_->Get(started.id());
    while (!IsFinalState(info.state())) info = runs_->AwaitChange(info.id(), info.state(), far);
    ASSERT_EQ(info.state(), v1::FINISHED) << info.message();
    const std::vector<std::string> stored = result(info.id());
    ASSERT_EQ(stored.size(), 11u);  // t = 0, 0.1, ..., 1 s

    // The store's copy replaced behind the manager's back (frames never change after a run's
    // end; this only shows which copy is read).
    EncodedFrameChunk other;
    other.frame_count = 1;
    std::vector<v1::Frame> one(1);
    one[0].set_seq(0);
    other.data = EncodeFrameChunks(one).front().data;
    store_->PutFrameChunk(info.id(), 0, other, "");
    v1::RunInfo changed = info;  // and its row (an ended run's info never changes either)
    changed.set_message("changed in the store");
    store_->PutRun(changed);
    const std::vector<std::string> again = result(info.id());
    if (kept_bytes > 0) {
      EXPECT_EQ(again, stored);
      EXPECT_EQ(runs_->Get(info.id()).message(), info.message());
    } else {
      EXPECT_EQ(again.size(), 1u);
      EXPECT_EQ(runs_->Get(info.id()).message(), "changed in the store");
    }
  }
}

TEST_F(RunManagerTest, SubscriberOfARunClaimedHereAndNotYetPreparedWaitsForIt) {
  runs_.reset();
  v1::RunInfo queued;
  queued.set_id("r-claimed-here");
  queued.set_state(v1::QUEUED);
  queued.set_created_unix_ms(1);
  store_->PutRun(queued);
  RunLease lease;
  lease.replica = "b";
  lease.now_unix_ms = 2;
  lease.expires_unix_ms = std::numeric_limits<int64_t>::max() / 2;  // never reaped here
  const std::optional<v1::RunInfo> claimed = store_->ClaimQueuedRun(lease);
  ASSERT_TRUE(claimed.has_value());
  ReplicaOptions replica;
  replica.id = "b";
  replica.private_store = false;
  RunManager b(models_.get(), store_.get(), limits_, &clock_, replica);

  std::atomic<bool> attached{false};
  std::shared_ptr<Subscription> subscription;
  std::thread subscriber([&] {
    subscription = b.subscriptions().SubscribeRun(claimed->id(), true);
    attached = true;
  });
  while (b.subscriptions().count() == 0) std::this_thread::yield();  // it is in SubscribeRun
  EXPECT_FALSE(attached.load()) << "the subscriber was answered while the run was being prepared";
  v1::RunInfo finished = *claimed;
  finished.set_state(v1::FINISHED);
  finished.set_ended_unix_ms(3);
  ASSERT_TRUE(store_->PutRunIfHeld(finished, LeaseHolder(*claimed)));
  subscriber.join();
  ASSERT_TRUE(subscription);
  std::deque<StreamEvent> events;
  int64_t missed = 0;
  while (events.size() < 2 && subscription->Pop(std::chrono::seconds(30), 16, &events, &missed)) {
  }
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, StreamEvent::Kind::kRunStarted);
  EXPECT_EQ(events[1].kind, StreamEvent::Kind::kRunEnded);
  EXPECT_EQ(b.Get(claimed->id()).state(), v1::FINISHED);
  b.subscriptions().Unsubscribe(subscription);
}

// Run ids: the store refuses one it holds already (another replica's, or a run of before)
// and the manager draws new ids for the whole batch; ids repeated within a batch are drawn
// again before anything is stored; when no free id turns up the batch is refused whole.
class RunIdCollisionTest : public RunManagerTest {
 protected:
  // Ids from `ids` in turn, then "r-fresh-1", "r-fresh-2", ...
  void DrawIds(std::vector<std::string> ids) {
    runs_->SetRunIdSourceForTesting([ids = std::move(ids), next = size_t{0}]() mutable {
      return next < ids.size() ? ids[next++] : "r-fresh-" + std::to_string(++next - ids.size());
    });
  }
  // An ended run stored under `id` as another replica would have, before this manager.
  v1::RunInfo StoreEndedRun(const std::string& id) {
    v1::RunInfo info;
    info.set_id(id);
    info.set_model_name("someone else's model");
    info.set_state(v1::FINISHED);
    info.set_message("stored before");
    store_->PutRun(info);
    return info;
  }
};

TEST_F(RunIdCollisionTest, AnIdTheStoreHoldsIsDrawnAgainAndTheStoredRunIsKept) {
  const v1::RunInfo before = StoreEndedRun("r-taken");
  DrawIds({"r-taken", "r-taken"});
  const v1::RunInfo started = runs_->Start("single_pendulum", Swing(0.2, 0.0));
  EXPECT_EQ(started.id(), "r-fresh-1");
  const std::optional<v1::RunInfo> kept = store_->GetRun("r-taken");
  ASSERT_TRUE(kept.has_value());
  EXPECT_EQ(kept->model_name(), before.model_name());
  EXPECT_EQ(kept->state(), v1::FINISHED);
  EXPECT_EQ(kept->message(), "stored before");
  const std::optional<v1::RunInfo> stored = store_->GetRun("r-fresh-1");
  ASSERT_TRUE(stored.has_value());
  EXPECT_EQ(stored->model_name(), "single_pendulum");
  // It runs to its end under its new id.
  const auto far = std::chrono::steady_clock::now() + std::chrono::hours(1);
  v1::RunInfo info = runs_->Get(started.id());
  while (!IsFinalState(info.state())) info = runs_->AwaitChange(info.id(), info.state(), far);
  EXPECT_EQ(info.state(), v1::FINISHED) << info.message();
}

TEST_F(RunIdCollisionTest, ABatchWithOneTakenIdIsStoredWholeUnderNewIds) {
  StoreEndedRun("r-taken");
  // The batch's first draw: one id taken in the store; the second: one id twice.
  DrawIds({"r-a", "r-taken", "r-b", "r-b"});
  google::protobuf::RepeatedPtrField<v1::RunSpec> specs;
  *specs.Add() = Swing(0.2, 0.0);
  *specs.Add() = Swing(0.2, 0.0);
  const std::vector<v1::RunInfo> started = runs_->StartMany("single_pendulum", specs);
  ASSERT_EQ(started.size(), 2u);
  EXPECT_EQ(started[0].id(), "r-fresh-1");
  EXPECT_EQ(started[1].id(), "r-fresh-2");
  // Nothing of the refused draw was stored: all or none.
  EXPECT_FALSE(store_->GetRun("r-a").has_value());
  EXPECT_FALSE(store_->GetRun("r-b").has_value());
  EXPECT_EQ(store_->GetRun("r-taken")->model_name(), "someone else's model");
}

TEST_F(RunIdCollisionTest, NoFreeIdRefusesTheBatchAndQueuesNothing) {
  StoreEndedRun("r-taken");
  runs_->SetRunIdSourceForTesting([] { return std::string("r-taken"); });
  EXPECT_THROW(runs_->Start("single_pendulum", Swing(0.2, 0.0)), std::exception);
  EXPECT_EQ(runs_->List("", 0, 0, "").runs.size(), 1u);  // only the run stored before
  // The manager goes on: with free ids the next run starts and ends.
  DrawIds({});
  const v1::RunInfo started = runs_->Start("single_pendulum", Swing(0.2, 0.0));
  EXPECT_EQ(started.id(), "r-fresh-1");
  const auto far = std::chrono::steady_clock::now() + std::chrono::hours(1);
  v1::RunInfo info = runs_->Get(started.id());
  while (!IsFinalState(info.state())) info = runs_->AwaitChange(info.id(), info.state(), far);
  EXPECT_EQ(info.state(), v1::FINISHED) << info.message();
}

// --min-free-mb: with less free space than the limit on the data directory's disk, Start and
// StartMany refuse new runs (RESOURCE_EXHAUSTED) with a message that says what to do, and
// store nothing; once space is freed, runs start again. The free space is injected.
TEST_F(RunManagerTest, TooLittleFreeSpaceRefusesNewRunsUntilSpaceIsFreed) {
  std::atomic<int64_t> free_bytes{int64_t{3} << 20};
  runs_->replica().SetFreeSpaceSource([&] { return std::optional<int64_t>(free_bytes.load()); },
                                      "/srv/mbstream-data");
  ASSERT_EQ(limits_.min_free_bytes, int64_t{64} << 20);  // the default
  try {
    runs_->Start("single_pendulum", Swing(0.5, 0.0));
    FAIL() << "a run started with 3 MiB free";
  } catch (const RequestError& error) {
    EXPECT_EQ(error.kind(), RequestErrorKind::kResourceExhausted);
    const std::string message = error.what();
    for (const char* part : {"/srv/mbstream-data", "3.0 MiB free", "--min-free-mb (64.0 MiB)",
                             "free space", "bigger one", "mbstream delete"}) {
      EXPECT_NE(message.find(part), std::string::npos) << part << " not in: " << message;
    }
  }
  google::protobuf::RepeatedPtrField<v1::RunSpec> specs;
  *specs.Add() = Swing(0.5, 0.0);
  *specs.Add() = Swing(0.5, 0.0);
  try {
    runs_->StartMany("single_pendulum", specs);
    FAIL() << "a sweep started with 3 MiB free";
  } catch (const RequestError& error) {
    EXPECT_EQ(error.kind(), RequestErrorKind::kResourceExhausted);
  }
  EXPECT_TRUE(runs_->List("", 0, 0, "").runs.empty());  // nothing stored

  free_bytes = limits_.min_free_bytes;  // exactly the margin: enough
  const v1::RunInfo started = runs_->Start("single_pendulum", Swing(0.5, 0.0));
  EXPECT_EQ(started.state(), v1::QUEUED);
  EXPECT_EQ(runs_->List("", 0, 0, "").runs.size(), 1u);
}

// Unknown free space (statvfs failed) does not stop the server from running.
TEST_F(RunManagerTest, UnknownFreeSpaceLetsRunsStart) {
  runs_->replica().SetFreeSpaceSource([] { return std::optional<int64_t>(); }, dir_.string());
  EXPECT_EQ(runs_->Start("single_pendulum", Swing(0.5, 0.0)).state(), v1::QUEUED);
}

TEST(FreeSpaceTest, ChecksTheSourceAgainstTheLimitAndZeroTurnsItOff) {
  const FreeSpaceSource one_mib = [] { return std::optional<int64_t>(int64_t{1} << 20); };
  EXPECT_THROW(CheckFreeSpace(one_mib, (int64_t{1} << 20) + 1, "d"), RequestError);
  EXPECT_NO_THROW(CheckFreeSpace(one_mib, int64_t{1} << 20, "d"));
  EXPECT_NO_THROW(CheckFreeSpace(one_mib, 0, "d"));                           // --min-free-mb 0
  EXPECT_NO_THROW(CheckFreeSpace(FreeSpaceSource(), int64_t{1} << 40, "d"));  // no source
}

TEST(FreeSpaceTest, FreeBytesAtReadsTheFileSystem) {
  const std::optional<int64_t> free_bytes = FreeBytesAt(fs::temp_directory_path().string());
  ASSERT_TRUE(free_bytes.has_value());
  EXPECT_GE(*free_bytes, 0);
  EXPECT_FALSE(FreeBytesAt("/no/such/directory/mbstream").has_value());
}

}  // namespace
}  // namespace mbstream

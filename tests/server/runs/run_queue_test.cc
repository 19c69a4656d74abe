// RunQueue alone, on a SQLite store, its runs "integrated" by a hook that waits for the manual
// clock, which also times the leases: workers take queued runs in order, a cancelled queued run
// is never taken, a claim whose lease expired is reaped when the clock passes it and taken here,
// a run whose lease another replica reaped is stopped at the next renewal, shutdown wakes the
// waiting workers and interrupts what is queued, a drained queue claims no more and hands its
// queued runs back; Attach finds the runs here.
#include "server/runs/run_queue.h"

#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include "server/runs/request_error.h"
#include "server/store/run_lease.h"
#include "server/store/store.h"
#include "tests/server/runs/manual_run_clock.h"

namespace mbstream {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;
using std::chrono::seconds;

class RunQueueTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mbstream-run-queue-" + std::to_string(getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    store_ = Store::Open(dir_.string());
  }
  void TearDown() override {
    if (queue_) queue_->Shutdown("the test ended");  // the hooks use queue_ until then
    queue_.reset();
    store_.reset();
    fs::remove_all(dir_);
  }

  // Replica "b", its leases timed by the manual clock; the keeper's own rounds and the idle
  // workers' looks at a shared store an hour apart (the test calls KeepLeases).
  void MakeQueue(bool private_store, int workers = 1, int max_queued_runs = 16) {
    ReplicaOptions replica;
    replica.id = "b";
    replica.private_store = private_store;
    replica.lease_timeout_s = 3600.0;
    replica.claim_poll_s = 3600.0;
    ServerLimits limits;
    limits.workers = workers;
    limits.max_queued_runs = max_queued_runs;
    RunQueue::Hooks hooks;
    hooks.new_run_id = [this] { return "r-" + std::to_string(++ids_); };
    hooks.prepare = [this](const v1::RunInfo& info) {
      std::lock_guard<std::mutex> lock(mutex_);
      prepared_.push_back(info);
      return MakeRun(info);
    };
    hooks.execute = [this](const std::shared_ptr<mbstream::Run>& run) { Integrate(run); };
    hooks.state_changed = [] {};
    queue_ = std::make_unique<RunQueue>(store_.get(), replica, limits, hooks, &clock_);
  }

  std::shared_ptr<mbstream::Run> MakeRun(const v1::RunInfo& info) {
    return std::make_shared<mbstream::Run>(info, RunConfig{}, std::make_shared<CompiledModel>(),
                                           clock_);
  }

  // Queues one run and returns its id.
  std::string Enqueue(int retries = 0) {
    std::vector<v1::RunInfo> infos(1);
    infos[0].set_state(v1::QUEUED);
    infos[0].set_created_unix_ms(++created_);
    infos[0].mutable_spec()->set_retries(retries);
    queue_->Enqueue(infos, [this](const v1::RunInfo& info, size_t) { return MakeRun(info); });
    return infos[0].id();
  }

  // A worker's run: integrates for integrate_for_ of the manual clock, or until cancelled.
  void Integrate(const std::shared_ptr<mbstream::Run>& run) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      started_.push_back(run->id());
    }
    run->UpdateInfo([](v1::RunInfo& info) { info.set_state(v1::RUNNING); });
    clock_.WaitUntil(clock_.Now() + integrate_for_, run->cancel);
    queue_->Release(run);
    run->End();
    std::lock_guard<std::mutex> lock(mutex_);
    ended_.push_back(run);
    changed_.notify_all();
  }

  // Waits until `count` runs have ended here.
  bool WaitForEnded(size_t count) {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_for(lock, seconds(30), [&] { return ended_.size() >= count; });
  }
  std::vector<std::string> Started() {
    std::lock_guard<std::mutex> lock(mutex_);
    return started_;
  }

  testing::ManualRunClock clock_;
  seconds integrate_for_{1};  // set before MakeQueue
  fs::path dir_;
  std::unique_ptr<Store> store_;
  std::unique_ptr<RunQueue> queue_;
  std::atomic<int> ids_{0};
  int64_t created_ = 0;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<std::string> started_;
  std::vector<std::shared_ptr<mbstream::Run>> ended_;
  std::vector<v1::RunInfo> prepared_;
};

TEST_F(RunQueueTest, WorkersTakeQueuedRunsInTheOrderTheyWereQueued) {
  MakeQueue(/*private_store=*/true);
  const std::string first = Enqueue();
  ASSERT_TRUE(clock_.WaitForWaiter().has_value());  // the one worker integrates it
  const std::string second = Enqueue(), third = Enqueue();
  EXPECT_EQ(queue_->Find(second)->state(), v1::QUEUED);
  EXPECT_TRUE(queue_->IntegratesHere(first));
  EXPECT_FALSE(queue_->IntegratesHere(second));
  EXPECT_EQ(queue_->NewestRunning()->id(), first);
  for (int i = 0; i < 3; ++i) {
    if (i > 0) {
      ASSERT_TRUE(clock_.WaitForWaiter().has_value());
    }
    clock_.Advance(seconds(1));
  }
  ASSERT_TRUE(WaitForEnded(3));
  EXPECT_EQ(Started(), (std::vector<std::string>{first, second, third}));
  EXPECT_EQ(queue_->Find(first), nullptr);  // released
  // A private store's claims are made in memory: the rows stay as Enqueue stored them.
  EXPECT_EQ(store_->GetRun(third)->state(), v1::QUEUED);
}

TEST_F(RunQueueTest, AFullQueueRefusesMoreRunsAndQueuesNoneOfThem) {
  MakeQueue(/*private_store=*/true, /*workers=*/1, /*max_queued_runs=*/2);
  std::vector<v1::RunInfo> infos(3);
  try {
    queue_->Enqueue(infos, [this](const v1::RunInfo& info, size_t) { return MakeRun(info); });
    FAIL() << "three runs went into a queue of two";
  } catch (const RequestError& error) {
    EXPECT_EQ(error.kind(), RequestErrorKind::kResourceExhausted);
  }
  EXPECT_TRUE(store_->ListRuns().empty());
}

TEST_F(RunQueueTest, ACancelledQueuedRunIsNeverTakenAndARunningOneStops) {
  MakeQueue(/*private_store=*/true);
  const std::string running = Enqueue();
  ASSERT_TRUE(clock_.WaitForWaiter().has_value());
  const std::string queued = Enqueue();
  const std::optional<v1::RunInfo> cancelled = queue_->Cancel(queued);
  ASSERT_TRUE(cancelled.has_value());
  EXPECT_EQ(cancelled->state(), v1::CANCELLED);
  EXPECT_EQ(store_->GetRun(queued)->state(), v1::CANCELLED);
  EXPECT_EQ(queue_->Find(queued), nullptr);

  ASSERT_TRUE(queue_->Cancel(running).has_value());  // cancel requested: it stops
  ASSERT_TRUE(WaitForEnded(1));
  EXPECT_TRUE(ended_[0]->cancel);
  EXPECT_EQ(Started(), std::vector<std::string>{running});
  EXPECT_FALSE(queue_->Cancel("r-unknown").has_value());
}

// Attach finds a run queued or integrating here; a run the store holds ended is not here, and
// one it does not hold is not found.
TEST_F(RunQueueTest, AttachFindsTheRunsHereAndTellsAnEndedOneFromAnUnknownOne) {
  MakeQueue(/*private_store=*/true);
  const std::string running = Enqueue();
  ASSERT_TRUE(clock_.WaitForWaiter().has_value());
  const std::string queued = Enqueue();
  v1::RunInfo ended;
  ended.set_id("r-ended");
  ended.set_state(v1::FINISHED);
  store_->PutRun(ended);
  auto subscriber = std::make_shared<Subscription>(16);
  EXPECT_EQ(queue_->Attach(subscriber, running, true), RunQueue::Attached::kAttached);
  EXPECT_EQ(queue_->Attach(subscriber, queued, true), RunQueue::Attached::kAttached);
  EXPECT_EQ(queue_->Find(running)->subscriber_count(), 1);
  EXPECT_EQ(queue_->Attach(subscriber, "r-ended", true), RunQueue::Attached::kNotHere);
  EXPECT_EQ(queue_->Attach(subscriber, "r-unknown", true), RunQueue::Attached::kNotFound);
  subscriber->Cancel();
}

TEST_F(RunQueueTest, AClaimIsReapedWhenTheClockPassesItsLeaseAndTakenHere) {
  v1::RunInfo info;
  info.set_id("r-of-a");
  info.set_state(v1::QUEUED);
  info.mutable_spec()->set_retries(1);
  store_->PutRun(info);
  RunLease lease;
  lease.replica = "a";
  lease.now_unix_ms = 0;
  lease.expires_unix_ms = 1000;
  ASSERT_TRUE(store_->ClaimQueuedRun(lease).has_value());  // replica a, which then dies
  MakeQueue(/*private_store=*/false);

  clock_.Advance(milliseconds(999));
  queue_->KeepLeases();
  EXPECT_EQ(store_->GetRun("r-of-a")->replica(), "a");
  EXPECT_TRUE(Started().empty());

  clock_.Advance(milliseconds(2));  // t = 1.001 s: a's lease expired
  queue_->KeepLeases();             // queued again (a retry left), the workers woken
  ASSERT_TRUE(clock_.WaitForWaiter().has_value());
  EXPECT_EQ(Started(), std::vector<std::string>{"r-of-a"});
  const v1::RunInfo claimed = store_->GetRun("r-of-a").value();
  EXPECT_EQ(claimed.state(), v1::RUNNING);
  EXPECT_EQ(claimed.replica(), "b");
  EXPECT_EQ(claimed.attempts(), 2);
  EXPECT_EQ(claimed.started_unix_ms(), 1001);  // the manual clock's time
  ASSERT_EQ(prepared_.size(), 1u);             // started elsewhere: prepared here
  EXPECT_TRUE(queue_->IntegratesHere("r-of-a"));
  EXPECT_TRUE(queue_->serving());
}

TEST_F(RunQueueTest, ARunWhoseLeaseAnotherReplicaReapedStopsAtTheNextRenewal) {
  integrate_for_ = std::chrono::hours(24);  // until cancelled
  MakeQueue(/*private_store=*/false);
  const std::string id = Enqueue();
  ASSERT_TRUE(clock_.WaitForWaiter().has_value());
  const int64_t expires = 3600 * 750;  // 3/4 of the lease timeout from t = 0
  EXPECT_EQ(queue_->NewLease().expires_unix_ms, expires);
  EXPECT_TRUE(store_->ReapExpiredLeases(expires, "c").empty());  // not expired yet
  queue_->KeepLeases();                                          // renewed: still this replica's
  ASSERT_TRUE(Started().size() == 1 && ended_.empty());

  // This replica stops renewing (as if it hung); replica c reaps the run after its lease.
  clock_.Advance(milliseconds(expires + 1));
  ASSERT_EQ(store_->ReapExpiredLeases(expires + 1, "c").size(), 1u);
  queue_->KeepLeases();
  ASSERT_TRUE(WaitForEnded(1));
  EXPECT_TRUE(ended_[0]->lease_lost);
  EXPECT_TRUE(ended_[0]->cancel);
  EXPECT_EQ(store_->GetRun(id)->state(), v1::INTERRUPTED);  // no retries left
}

TEST_F(RunQueueTest, ShutdownWakesTheWaitingWorkers) {
  MakeQueue(/*private_store=*/true, /*workers=*/3);
  EXPECT_TRUE(queue_->Shutdown("the test stopped"));  // returns: every worker was woken
  EXPECT_FALSE(queue_->Shutdown("again"));
  EXPECT_EQ(queue_->stop_reason(), "the test stopped");
  EXPECT_FALSE(queue_->serving());
  try {
    Enqueue();
    FAIL() << "a stopped queue took a run";
  } catch (const RequestError& error) {
    EXPECT_EQ(error.kind(), RequestErrorKind::kUnavailable);
  }
}

TEST_F(RunQueueTest, ShutdownInterruptsTheRunningRunAndEndsTheQueuedOnes) {
  MakeQueue(/*private_store=*/true);
  const std::string running = Enqueue();
  ASSERT_TRUE(clock_.WaitForWaiter().has_value());
  const std::string queued = Enqueue();
  const std::shared_ptr<mbstream::Run> waiting = queue_->Find(queued);
  ASSERT_TRUE(queue_->Shutdown("the test stopped"));
  ASSERT_EQ(ended_.size(), 1u);  // the worker was joined
  EXPECT_TRUE(ended_[0]->interrupted);
  EXPECT_EQ(Started(), std::vector<std::string>{running});
  const v1::RunInfo stored = store_->GetRun(queued).value();
  EXPECT_EQ(stored.state(), v1::INTERRUPTED);
  EXPECT_EQ(stored.message(), "the test stopped before this run started");
  EXPECT_TRUE(waiting->ended());
}

TEST_F(RunQueueTest, ADrainedQueueClaimsNoMoreAndHandsItsQueuedRunsBack) {
  MakeQueue(/*private_store=*/false);
  std::vector<bool> serving;
  queue_->SetServingListener([&](bool now) { serving.push_back(now); });
  const std::string running = Enqueue();
  ASSERT_TRUE(clock_.WaitForWaiter().has_value());
  const std::string queued = Enqueue();
  std::thread drain([&] { queue_->Drain(std::chrono::seconds(30)); });
  while (queue_->serving()) std::this_thread::yield();  // draining: no more claims
  try {
    Enqueue();
    FAIL() << "a draining queue took a run";
  } catch (const RequestError& error) {
    EXPECT_EQ(error.kind(), RequestErrorKind::kUnavailable);
  }
  clock_.Advance(seconds(1));  // the running run ends; Drain returns
  drain.join();
  ASSERT_TRUE(queue_->Shutdown("drained"));
  EXPECT_EQ(Started(), std::vector<std::string>{running});
  const v1::RunInfo stored = store_->GetRun(queued).value();
  EXPECT_EQ(stored.state(), v1::QUEUED);  // for another replica
  EXPECT_TRUE(stored.replica().empty());
  EXPECT_EQ(serving, (std::vector<bool>{true, false}));
}

}  // namespace
}  // namespace mbstream

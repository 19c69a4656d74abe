// Retention with a manual clock: the oldest ended runs beyond --retain-runs or older than
// --retain-days are deleted, never a kept one nor a queued or running one; the plan (dry run)
// is what a pass deletes; a run marked keep after the plan was made stays.
#include "server/runs/retention.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>

#include <unistd.h>

#include "server/runs/model_registry.h"
#include "server/runs/run_deleter.h"
#include "server/runs/run_manager.h"
#include "server/store/store.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

namespace fs = std::filesystem;
constexpr int64_t kDayMs = 86400000;
constexpr int64_t kStartMs = 1'800'000'000'000;  // the manual clock's day 0

class RetentionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mbstream-retention-" + std::to_string(getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    store_ = Store::Open(dir_.string());
    models_ = std::make_unique<ModelRegistry>(store_.get(), limits_);
    runs_ = std::make_unique<RunManager>(models_.get(), store_.get(), limits_);
    deleter_ = std::make_unique<RunDeleter>(store_.get(), runs_.get(), models_.get());
  }
  void TearDown() override {
    deleter_.reset();
    runs_.reset();
    models_.reset();
    store_.reset();
    fs::remove_all(dir_);
  }

  // Run `id` in `state`, created and (when final) ended on day `day` of the manual clock.
  void PutRun(const std::string& id, v1::RunState state, double day) {
    v1::RunInfo info;
    info.set_id(id);
    info.set_model_id("m-x");
    info.set_state(state);
    info.set_created_unix_ms(kStartMs + static_cast<int64_t>(day * kDayMs));
    if (state != v1::QUEUED && state != v1::RUNNING) info.set_ended_unix_ms(info.created_unix_ms());
    store_->PutRun(info);
  }
  std::unique_ptr<Retention> MakeRetention(RetentionPolicy policy) {
    return std::make_unique<Retention>(store_.get(), deleter_.get(), policy,
                                       [this] { return now_ms_; });
  }
  std::vector<std::string> IdsOf(const std::vector<v1::RunInfo>& runs) {
    std::vector<std::string> ids;
    for (const v1::RunInfo& run : runs) ids.push_back(run.id());
    return ids;
  }
  std::vector<std::string> StoredIds() { return IdsOf(store_->ListRuns()); }

  fs::path dir_;
  ServerLimits limits_;
  int64_t now_ms_ = kStartMs;
  std::unique_ptr<Store> store_;
  std::unique_ptr<ModelRegistry> models_;
  std::unique_ptr<RunManager> runs_;
  std::unique_ptr<RunDeleter> deleter_;
};

using Ids = std::vector<std::string>;

TEST_F(RetentionTest, RetainRunsKeepsTheNewestEndedRunsAndEveryKeptOrUnfinishedOne) {
  PutRun("r-1", v1::FINISHED, 0);
  PutRun("r-2", v1::FAILED, 1);
  PutRun("r-3", v1::CANCELLED, 2);
  PutRun("r-4", v1::FINISHED, 3);
  PutRun("r-5", v1::INTERRUPTED, 4);
  PutRun("r-6", v1::QUEUED, 5);  // never: not ended (a worker may claim it)
  ASSERT_TRUE(store_->SetRunKeep("r-2", true));
  RetentionPolicy policy;
  policy.retain_runs = 2;
  std::unique_ptr<Retention> retention = MakeRetention(policy);

  // Ended and not kept: r-1, r-3, r-4, r-5; the newest two stay.
  EXPECT_EQ(IdsOf(retention->Plan()), (Ids{"r-1", "r-3"}));
  EXPECT_EQ(StoredIds().size(), 6u);  // a plan deletes nothing
  EXPECT_EQ(retention->Sweep(), 2);
  EXPECT_EQ(StoredIds(), (Ids{"r-2", "r-4", "r-5", "r-6"}));
  EXPECT_TRUE(store_->GetRun("r-2")->keep());
  EXPECT_TRUE(retention->Plan().empty());
  EXPECT_EQ(retention->Sweep(), 0);

  PutRun("r-7", v1::FINISHED, 6);  // one more ended: the oldest unkept ended one goes
  EXPECT_EQ(retention->Sweep(), 1);
  EXPECT_EQ(StoredIds(), (Ids{"r-2", "r-5", "r-6", "r-7"}));
}

TEST_F(RetentionTest, RetainDaysDeletesWhatEndedBeforeAsTheClockAdvances) {
  for (int day = 0; day < 6; ++day) PutRun("r-" + std::to_string(day), v1::FINISHED, day);
  PutRun("r-queued", v1::QUEUED, 0);  // (a RUNNING row without a lease would be reaped)
  RetentionPolicy policy;
  policy.retain_days = 2.5;
  std::unique_ptr<Retention> retention = MakeRetention(policy);

  now_ms_ = kStartMs + 2 * kDayMs;  // nothing is 2.5 days old yet
  EXPECT_EQ(retention->Sweep(), 0);
  now_ms_ = kStartMs + 4 * kDayMs;  // days 0 and 1 ended more than 2.5 days ago
  EXPECT_EQ(IdsOf(retention->Plan()), (Ids{"r-0", "r-1"}));
  EXPECT_EQ(retention->Sweep(), 2);
  now_ms_ = kStartMs + 100 * kDayMs;  // every ended run, never the queued one
  EXPECT_EQ(retention->Sweep(), 4);
  EXPECT_EQ(StoredIds(), (Ids{"r-queued"}));
}

TEST_F(RetentionTest, ARunMarkedKeepAfterThePlanStays) {
  PutRun("r-1", v1::FINISHED, 0);
  PutRun("r-2", v1::FINISHED, 1);
  RetentionPolicy policy;
  policy.retain_runs = 1;
  std::unique_ptr<Retention> retention = MakeRetention(policy);
  ASSERT_EQ(IdsOf(retention->Plan()), (Ids{"r-1"}));
  ASSERT_TRUE(store_->SetRunKeep("r-1", true));  // between the plan and the deletion
  EXPECT_FALSE(deleter_->DeleteIfEnded("r-1"));
  EXPECT_EQ(retention->Sweep(), 0);  // kept runs do not count: r-2 is the one retained
  ASSERT_TRUE(store_->SetRunKeep("r-1", false));
  EXPECT_EQ(retention->Sweep(), 1);
  EXPECT_EQ(StoredIds(), (Ids{"r-2"}));
}

TEST_F(RetentionTest, NoPolicyDeletesNothingAndStartsNoThread) {
  PutRun("r-1", v1::FINISHED, 0);
  std::unique_ptr<Retention> retention = MakeRetention(RetentionPolicy());
  now_ms_ = kStartMs + 1000 * kDayMs;
  EXPECT_TRUE(retention->Plan().empty());
  retention->Start(0.01);
  EXPECT_EQ(retention->Sweep(), 0);
  retention->Stop();
  EXPECT_EQ(StoredIds(), (Ids{"r-1"}));
}

TEST_F(RetentionTest, TheBackgroundPassDeletesWithoutBeingAsked) {
  PutRun("r-1", v1::FINISHED, 0);
  PutRun("r-2", v1::FINISHED, 1);
  RetentionPolicy policy;
  policy.retain_runs = 1;
  std::unique_ptr<Retention> retention = MakeRetention(policy);
  retention->Start(0.01);
  // Waits for the event (the run gone), reading the store; bounded.
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (store_->GetRun("r-1") && std::chrono::steady_clock::now() < until) {
    std::this_thread::yield();
  }
  retention->Stop();
  EXPECT_EQ(StoredIds(), (Ids{"r-2"}));
}

// Runs `ids` of model `model` (name and id), ended on days 0, 1, 2, ... in order.
std::vector<v1::RunInfo> EndedRuns(const std::string& model, const std::vector<std::string>& ids,
                                   double first_day) {
  std::vector<v1::RunInfo> runs;
  for (const std::string& id : ids) {
    v1::RunInfo& run = runs.emplace_back();
    run.set_id(id);
    run.set_model_id("m-" + model);
    run.set_model_name(model);
    run.set_state(v1::FINISHED);
    run.set_created_unix_ms(kStartMs + static_cast<int64_t>((first_day + runs.size()) * kDayMs));
    run.set_ended_unix_ms(run.created_unix_ms());
  }
  return runs;
}

std::vector<std::string> IdsOf(const std::vector<v1::RunInfo>& runs) {
  std::vector<std::string> ids;
  for (const v1::RunInfo& run : runs) ids.push_back(run.id());
  return ids;
}

// --retain-model: a model's runs are kept by its own limits (by name or id) and count only
// against those; the other runs by the server's.
TEST(ModelRetentionTest, EachModelIsKeptByItsOwnLimits) {
  RetentionPolicy policy;
  policy.retain_runs = 2;
  AddModelRetention("arm=1", policy);          // by name: the newest one
  AddModelRetention("m-gripper=0,3", policy);  // by id: those ended within 3 days
  std::vector<v1::RunInfo> runs = EndedRuns("other", {"o-1", "o-2", "o-3"}, 0);
  for (const v1::RunInfo& run : EndedRuns("arm", {"a-1", "a-2", "a-3"}, 0)) runs.push_back(run);
  for (const v1::RunInfo& run : EndedRuns("gripper", {"g-1", "g-2", "g-3", "g-4"}, 0)) {
    runs.push_back(run);
  }
  std::stable_sort(runs.begin(), runs.end(), [](const v1::RunInfo& a, const v1::RunInfo& b) {
    return a.created_unix_ms() < b.created_unix_ms();
  });
  const int64_t now = kStartMs + 5 * kDayMs;  // g-1 (day 1) is 4 days old, g-2 3 days
  EXPECT_EQ(IdsOf(RetentionPlan(runs, policy, now)),
            (std::vector<std::string>{"o-1", "a-1", "g-1", "a-2"}));
  EXPECT_EQ(LimitsFor(policy, runs[0]).retain_runs, 2);    // o-1: the server's
  EXPECT_EQ(LimitsFor(policy, runs[2]).retain_days, 3.0);  // g-1: its model's

  RetentionPolicy only_models;  // no server limits: the other runs stay
  AddModelRetention("arm=1", only_models);
  EXPECT_TRUE(only_models.active());
  EXPECT_EQ(IdsOf(RetentionPlan(runs, only_models, now)), (std::vector<std::string>{"a-1", "a-2"}));
}

TEST(ModelRetentionTest, AWrongValueSaysTheExpectedForm) {
  for (const char* wrong :
       {"arm", "=3", "arm=", "arm=x", "arm=-1", "arm=2,", "arm=2,x", "arm=2;3", "arm=2,-1"}) {
    RetentionPolicy policy;
    try {
      AddModelRetention(wrong, policy);
      ADD_FAILURE() << wrong << " accepted";
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find("MODEL=RUNS,DAYS"), std::string::npos) << wrong;
    }
    EXPECT_TRUE(policy.models.empty()) << wrong;
  }
  RetentionPolicy policy;
  AddModelRetention("a=b=4,1.5", policy);  // a name may hold '=': the last one splits
  EXPECT_EQ(policy.models.at("a=b").retain_runs, 4);
  EXPECT_EQ(policy.models.at("a=b").retain_days, 1.5);
}

}  // namespace
}  // namespace mbstream

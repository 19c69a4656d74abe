#include "server/runs/retention.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <exception>

#include "common/check.h"
#include "server/runs/run_deleter.h"
#include "server/runs/unix_time.h"
#include "server/store/store.h"
#include "server/wire/stats_conversion.h"

namespace mbstream {

std::vector<v1::RunInfo> RetentionPlan(const std::vector<v1::RunInfo>& runs,
                                       const RetentionPolicy& policy, int64_t now_unix_ms) {
  std::vector<v1::RunInfo> plan;
  if (!policy.active()) return plan;
  constexpr double kMsPerDay = 86400e3;
  const int64_t oldest_kept_ms =
      policy.retain_days > 0.0 ? now_unix_ms - static_cast<int64_t>(policy.retain_days * kMsPerDay)
                               : INT64_MIN;
  int64_t candidates = 0;  // ended, unkept: what --retain-runs counts
  for (const v1::RunInfo& run : runs) {
    candidates += IsFinalState(run.state()) && !run.keep() ? 1 : 0;
  }
  for (const v1::RunInfo& run : runs) {  // oldest first
    if (!IsFinalState(run.state()) || run.keep()) continue;
    const bool too_many = policy.retain_runs > 0 && candidates > policy.retain_runs;
    const int64_t ended_ms = run.ended_unix_ms() > 0 ? run.ended_unix_ms() : run.created_unix_ms();
    if (too_many || ended_ms < oldest_kept_ms) {
      plan.push_back(run);
      --candidates;
    }
  }
  return plan;
}

Retention::Retention(Store* store, const RunDeleter* deleter, RetentionPolicy policy, Clock clock)
    : store_(store), deleter_(deleter), policy_(policy), clock_(std::move(clock)) {
  MBSTREAM_CHECK(store_ != nullptr && deleter_ != nullptr);
  if (!clock_) clock_ = [] { return NowUnixMs(); };
}

Retention::~Retention() { Stop(); }

std::vector<v1::RunInfo> Retention::Plan() const {
  return RetentionPlan(store_->ListRuns(), policy_, clock_());
}

int Retention::Sweep() {
  int deleted = 0;
  try {
    for (const v1::RunInfo& run : Plan()) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        if (stop_) break;
      }
      if (deleter_->DeleteIfEnded(run.id())) ++deleted;
    }
  } catch (const std::exception& error) {
    spdlog::error("retention: {}; the next pass tries again", error.what());
  }
  if (deleted > 0) spdlog::info("retention deleted {} runs", deleted);
  return deleted;
}

void Retention::Start(double period_s) {
  if (!policy_.active() || thread_.joinable()) return;
  thread_ = std::thread([this, period_s] {
    const auto period = std::chrono::duration<double>(period_s);
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stop_) {
      lock.unlock();
      Sweep();
      lock.lock();
      wake_.wait_for(lock, period, [this] { return stop_; });
    }
  });
}

void Retention::Stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

}  // namespace mbstream

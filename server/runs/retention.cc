#include "server/runs/retention.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <exception>
#include <map>
#include <stdexcept>

#include "server/runs/run_deleter.h"
#include "server/runs/unix_time.h"
#include "server/store/store.h"
#include "server/wire/stats_conversion.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

// The key of the group of limits that keep `run` ("" for the server's own).
std::string GroupOf(const RetentionPolicy& policy, const v1::RunInfo& run) {
  if (policy.models.count(run.model_name()) > 0) return run.model_name();
  if (policy.models.count(run.model_id()) > 0) return run.model_id();
  return "";
}

}  // namespace

ModelRetention LimitsFor(const RetentionPolicy& policy, const v1::RunInfo& run) {
  const std::string group = GroupOf(policy, run);
  return group.empty() ? ModelRetention{policy.retain_runs, policy.retain_days}
                       : policy.models.at(group);
}

void AddModelRetention(const std::string& text, RetentionPolicy& policy) {
  const size_t equals = text.rfind('=');
  const std::string form = "--retain-model '" + text +
                           "': expected MODEL=RUNS or MODEL=RUNS,DAYS (a model's name or id, the "
                           "newest RUNS ended runs kept, DAYS days; 0 = no limit)";
  if (equals == std::string::npos || equals == 0) throw InputError(form);
  ModelRetention limits;
  try {
    size_t used = 0;
    const std::string numbers = text.substr(equals + 1);
    limits.retain_runs = std::stoll(numbers, &used);
    if (used < numbers.size()) {
      if (numbers[used] != ',') throw InputError(form);
      const std::string days = numbers.substr(used + 1);
      limits.retain_days = std::stod(days, &used);
      if (used != days.size()) throw InputError(form);
    }
  } catch (const std::logic_error&) {  // stoll, stod: not a number
    throw InputError(form);
  }
  if (limits.retain_runs < 0 || !(limits.retain_days >= 0.0)) throw InputError(form);
  policy.models[text.substr(0, equals)] = limits;
}

std::vector<v1::RunInfo> RetentionPlan(const std::vector<v1::RunInfo>& runs,
                                       const RetentionPolicy& policy, int64_t now_unix_ms) {
  std::vector<v1::RunInfo> plan;
  if (!policy.active()) return plan;
  constexpr double kMsPerDay = 86400e3;
  std::map<std::string, int64_t> candidates;  // per group: ended, unkept (what RUNS counts)
  for (const v1::RunInfo& run : runs) {
    if (IsFinalState(run.state()) && !run.keep()) ++candidates[GroupOf(policy, run)];
  }
  for (const v1::RunInfo& run : runs) {  // oldest first
    if (!IsFinalState(run.state()) || run.keep()) continue;
    const ModelRetention limits = LimitsFor(policy, run);
    int64_t& left = candidates[GroupOf(policy, run)];
    const bool too_many = limits.retain_runs > 0 && left > limits.retain_runs;
    const int64_t oldest_kept_ms =
        limits.retain_days > 0.0
            ? now_unix_ms - static_cast<int64_t>(limits.retain_days * kMsPerDay)
            : INT64_MIN;
    const int64_t ended_ms = run.ended_unix_ms() > 0 ? run.ended_unix_ms() : run.created_unix_ms();
    if (too_many || ended_ms < oldest_kept_ms) {
      plan.push_back(run);
      --left;
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

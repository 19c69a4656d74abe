#include "server/runs/sweep_feeder.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <set>

#include "server/store/store.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

// Plans kept beyond the open sweeps' (GetSweep of sweeps that ended).
constexpr size_t kSparePlans = 16;

}  // namespace

SweepFeeder::SweepFeeder(Store* store, std::chrono::milliseconds poll, Feed feed,
                         std::function<void()> after_round)
    : store_(store), poll_(poll), feed_(std::move(feed)), after_round_(std::move(after_round)) {
  MBSTREAM_CHECK(store_ != nullptr && feed_ && poll_.count() > 0);
}

SweepFeeder::~SweepFeeder() { Stop(); }

void SweepFeeder::Start() {
  std::lock_guard lock(mutex_);
  if (!thread_.joinable() && !stop_) thread_ = std::thread([this] { Loop(); });
}

void SweepFeeder::Stop() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void SweepFeeder::Wake() {
  {
    std::lock_guard lock(mutex_);
    woken_ = true;
  }
  wake_.notify_one();
}

int SweepFeeder::PointsToQueue(int window, int room, int left) {
  const int count = std::min(room, left);
  if (count <= 0) return 0;
  return count >= std::max(1, window / 4) || count == left ? count : 0;
}

std::shared_ptr<const SweepPlan> SweepFeeder::Plan(const StoredSweep& sweep) const {
  {
    std::lock_guard lock(mutex_);
    if (auto found = plans_.find(sweep.id); found != plans_.end()) return found->second;
  }
  std::optional<StoredSweep> stored = store_->GetSweep(sweep.id, true);
  if (!stored) throw InputError("sweep " + sweep.id + " is not stored");
  v1::SweepDefinition definition;
  if (!definition.ParseFromString(stored->definition)) {
    throw InputError("sweep " + sweep.id + ": its stored definition is damaged");
  }
  auto plan = std::make_shared<const SweepPlan>(std::move(definition));
  std::lock_guard lock(mutex_);
  plans_[sweep.id] = plan;
  return plan;
}

void SweepFeeder::Remember(const std::string& sweep_id, std::shared_ptr<const SweepPlan> plan) {
  std::lock_guard lock(mutex_);
  plans_[sweep_id] = std::move(plan);
}

void SweepFeeder::RunRound() {
  std::lock_guard round(round_mutex_);
  std::vector<StoredSweep> open;
  try {
    open = store_->ListOpenSweeps();
  } catch (const std::exception& error) {
    spdlog::error("sweeps: listing the open sweeps failed: {}", error.what());
    return;
  }
  for (const StoredSweep& sweep : open) {
    const int count = PointsToQueue(sweep.window, sweep.window - sweep.unfinished_runs,
                                    sweep.total_points - sweep.next_point);
    if (count == 0) continue;
    try {
      feed_(sweep, *Plan(sweep), sweep.next_point, count);
    } catch (const std::exception& error) {
      spdlog::error("sweep {}: queueing points {}..{} failed: {}", sweep.id, sweep.next_point,
                    sweep.next_point + count - 1, error.what());
    }
  }
  // Forget the plans of sweeps no longer open, but a few.
  std::set<std::string> keep;
  for (const StoredSweep& sweep : open) keep.insert(sweep.id);
  std::lock_guard lock(mutex_);
  for (auto it = plans_.begin(); it != plans_.end() && plans_.size() > keep.size() + kSparePlans;) {
    it = keep.count(it->first) ? std::next(it) : plans_.erase(it);
  }
}

void SweepFeeder::Loop() {
  for (;;) {
    {
      std::unique_lock lock(mutex_);
      wake_.wait_for(lock, poll_, [&] { return stop_ || woken_; });
      if (stop_) return;
      woken_ = false;
    }
    RunRound();
    if (after_round_) after_round_();
  }
}

}  // namespace mbstream

#include "server/runs/cluster_follow.h"

#include <spdlog/spdlog.h>

#include <vector>

#include "server/store/store.h"

namespace mbstream {

ClusterFollow::ClusterFollow(Store* store, std::string replica_id,
                             std::chrono::duration<double> period, std::function<bool()> wanted,
                             std::function<void(const v1::RunInfo&)> announce)
    : store_(store),
      replica_id_(std::move(replica_id)),
      period_(period),
      wanted_(std::move(wanted)),
      announce_(std::move(announce)),
      thread_([this] { Loop(); }) {}

ClusterFollow::~ClusterFollow() { Stop(); }

void ClusterFollow::Stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

std::optional<v1::RunInfo> ClusterFollow::Attach() {
  bool first = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    first = !active_;
    active_ = true;
    ++attaches_;
  }
  std::optional<v1::RunInfo> newest = Look(false, first);
  wake_.notify_all();
  return newest;
}

std::optional<v1::RunInfo> ClusterFollow::Look(bool announce_new, bool note_seen) {
  std::vector<v1::RunInfo> running;
  try {
    running = store_->ListRunningRuns();
  } catch (const std::exception& error) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!store_failed_) {
      spdlog::warn("replica {}: listing the cluster's running runs for followers failed: {}",
                   replica_id_, error.what());
    }
    store_failed_ = true;
    return std::nullopt;
  }
  std::set<std::string> now;
  std::vector<const v1::RunInfo*> fresh;
  const v1::RunInfo* newest = nullptr;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    store_failed_ = false;
    for (const v1::RunInfo& info : running) {
      std::string key = info.id() + "/" + std::to_string(info.attempts());
      const bool elsewhere = info.replica() != replica_id_;
      if (elsewhere && (newest == nullptr || info.started_unix_ms() > newest->started_unix_ms())) {
        newest = &info;
      }
      if (announce_new && elsewhere && !seen_.count(key)) fresh.push_back(&info);
      now.insert(std::move(key));
    }
    if (note_seen) seen_.swap(now);
  }
  for (const v1::RunInfo* info : fresh) announce_(*info);
  if (newest == nullptr) return std::nullopt;
  return *newest;
}

void ClusterFollow::Loop() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_) {
    wake_.wait_for(lock, period_, [&] { return stop_; });
    if (stop_ || !active_) {
      if (!active_) wake_.wait(lock, [&] { return stop_ || active_; });
      continue;
    }
    const uint64_t attaches = attaches_;
    lock.unlock();
    const bool wanted = wanted_();
    if (wanted) Look(true, true);
    lock.lock();
    // No follower: the next one notes the running runs again (unless one attached meanwhile).
    if (!wanted && attaches == attaches_) active_ = false;
  }
}

}  // namespace mbstream

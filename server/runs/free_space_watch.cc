#include "server/runs/free_space_watch.h"

#include <spdlog/spdlog.h>

#include <chrono>

namespace mbstream {

FreeSpaceWatch::FreeSpaceWatch(FreeSpaceSource source, int64_t min_free_bytes)
    : source_(std::move(source)), min_free_bytes_(min_free_bytes) {}

FreeSpaceWatch::~FreeSpaceWatch() { Stop(); }

bool FreeSpaceWatch::Check() {
  const std::optional<int64_t> free = source_ ? source_() : std::nullopt;
  const bool enough = min_free_bytes_ <= 0 || !free || *free >= min_free_bytes_;
  std::lock_guard order(listener_mutex_);
  Listener listener;
  bool changed = false;
  {
    std::lock_guard lock(mutex_);
    free_bytes_ = free;
    changed = enough != enough_;
    enough_ = enough;
    listener = listener_;
  }
  if (changed) {
    if (enough) {
      spdlog::info(
          "free space on the data directory's disk is back above --min-free-mb: new "
          "runs are accepted again");
    } else {
      spdlog::warn(
          "free space on the data directory's disk ({} bytes) is below --min-free-mb "
          "({} bytes): new runs are refused until space is freed (mbstream delete, "
          "--retain-runs/--retain-days, a bigger disk)",
          free.value_or(-1), min_free_bytes_);
    }
    if (listener) listener(enough);
  }
  return enough;
}

void FreeSpaceWatch::SetListener(Listener listener) {
  std::lock_guard order(listener_mutex_);
  bool enough = true;
  {
    std::lock_guard lock(mutex_);
    listener_ = listener;
    enough = enough_;
  }
  if (listener) listener(enough);
}

void FreeSpaceWatch::Start(double period_s) {
  Check();
  thread_ = std::thread([this, period_s] {
    std::unique_lock lock(mutex_);
    while (!stop_) {
      wake_.wait_for(lock, std::chrono::duration<double>(period_s), [this] { return stop_; });
      if (stop_) break;
      lock.unlock();
      Check();
      lock.lock();
    }
  });
}

void FreeSpaceWatch::Stop() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

std::optional<int64_t> FreeSpaceWatch::free_bytes() const {
  std::lock_guard lock(mutex_);
  return free_bytes_;
}

bool FreeSpaceWatch::enough() const {
  std::lock_guard lock(mutex_);
  return enough_;
}

}  // namespace mbstream

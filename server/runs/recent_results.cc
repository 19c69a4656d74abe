#include "server/runs/recent_results.h"

#include <algorithm>
#include <utility>

namespace mbstream {

void RecentResults::Put(const v1::RunInfo& info, std::string chunk) {
  const std::string& run_id = info.id();
  std::lock_guard<std::mutex> lock(mutex_);
  EraseLocked(run_id);  // never a stale copy
  const std::size_t bytes = chunk.size() + info.ByteSizeLong();
  if (bytes > max_bytes_) return;
  bytes_ += bytes;
  kept_.emplace(run_id, Kept{info, std::move(chunk), bytes});
  order_.push_back(run_id);
  while (bytes_ > max_bytes_) {
    auto oldest = kept_.find(order_.front());
    bytes_ -= oldest->second.bytes;
    kept_.erase(oldest);
    order_.pop_front();
  }
}

void RecentResults::Erase(const std::string& run_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  EraseLocked(run_id);
}

void RecentResults::EraseLocked(const std::string& run_id) {
  auto kept = kept_.find(run_id);
  if (kept == kept_.end()) return;
  bytes_ -= kept->second.bytes;
  kept_.erase(kept);
  order_.erase(std::find(order_.begin(), order_.end(), run_id));
}

bool RecentResults::Get(const std::string& run_id, std::string& chunk) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto kept = kept_.find(run_id);
  if (kept == kept_.end()) return false;
  chunk.assign(kept->second.chunk);
  return true;
}

bool RecentResults::GetInfo(const std::string& run_id, v1::RunInfo& info) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto kept = kept_.find(run_id);
  if (kept == kept_.end()) return false;
  info = kept->second.info;
  return true;
}

std::size_t RecentResults::bytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return bytes_;
}

}  // namespace mbstream

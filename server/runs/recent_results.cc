#include "server/runs/recent_results.h"

#include <algorithm>
#include <utility>

namespace mbstream {

void RecentResults::Put(const std::string& run_id, std::string chunk) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (auto kept = chunks_.find(run_id); kept != chunks_.end()) {  // never a stale copy
    bytes_ -= kept->second.size();
    chunks_.erase(kept);
    order_.erase(std::find(order_.begin(), order_.end(), run_id));
  }
  if (chunk.size() > max_bytes_) return;
  bytes_ += chunk.size();
  chunks_.emplace(run_id, std::move(chunk));
  order_.push_back(run_id);
  while (bytes_ > max_bytes_) {
    auto oldest = chunks_.find(order_.front());
    bytes_ -= oldest->second.size();
    chunks_.erase(oldest);
    order_.pop_front();
  }
}

bool RecentResults::Get(const std::string& run_id, std::string& chunk) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto kept = chunks_.find(run_id);
  if (kept == chunks_.end()) return false;
  chunk.assign(kept->second);
  return true;
}

std::size_t RecentResults::bytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return bytes_;
}

}  // namespace mbstream

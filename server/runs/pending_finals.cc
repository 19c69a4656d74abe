#include "server/runs/pending_finals.h"

#include <spdlog/spdlog.h>

#include <vector>

#include "server/store/store.h"

namespace mbstream {

void PendingFinals::Add(const v1::RunInfo& info) {
  std::lock_guard lock(mutex_);
  pending_[info.id()] = info;
}

void PendingFinals::Erase(const std::string& run_id) {
  std::lock_guard lock(mutex_);
  pending_.erase(run_id);
}

bool PendingFinals::Find(const std::string& run_id, v1::RunInfo& info) const {
  std::lock_guard lock(mutex_);
  if (pending_.empty()) return false;
  auto found = pending_.find(run_id);
  if (found == pending_.end()) return false;
  info = found->second;
  return true;
}

size_t PendingFinals::size() const {
  std::lock_guard lock(mutex_);
  return pending_.size();
}

size_t PendingFinals::Retry(Store& store) {
  std::lock_guard retry(retry_mutex_);
  std::vector<v1::RunInfo> infos;
  {
    std::lock_guard lock(mutex_);
    if (pending_.empty()) return 0;
    for (const auto& [id, info] : pending_) infos.push_back(info);
  }
  for (const v1::RunInfo& info : infos) {
    try {
      store.PutRun(info);
    } catch (const std::exception& error) {
      spdlog::debug("run {}: its final state is still not stored: {}", info.id(), error.what());
      continue;
    }
    spdlog::info("run {}: its final state {} is stored now", info.id(),
                 v1::RunState_Name(info.state()));
    std::lock_guard lock(mutex_);
    pending_.erase(info.id());
  }
  return size();
}

}  // namespace mbstream

#include "server/service/replay_inbox.h"

#include <spdlog/spdlog.h>

namespace mbstream {

ReplayInbox::ReplayInbox(RunManager* runs, v1::ProbeSet set, int64_t max_reports)
    : runs_(runs), set_(std::move(set)), max_reports_(max_reports) {}

ReplayInbox::~ReplayInbox() {
  try {
    Flush();
  } catch (const std::exception& e) {
    spdlog::error("probe set {} of run {}: {} reports not stored: {}", set_.id(), set_.run_id(),
                  buffered_.size(), e.what());
  }
}

void ReplayInbox::PushControl(const v1::ReplayControl& control) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (controls_.size() >= kMaxControls) return;
    controls_.push_back(control);
  }
  arrived_.notify_all();
}

void ReplayInbox::Wake() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    woken_ = true;
  }
  arrived_.notify_all();
}

bool ReplayInbox::NextControl(Clock::time_point deadline, v1::ReplayControl* control) {
  std::unique_lock<std::mutex> lock(mutex_);
  arrived_.wait_until(lock, deadline, [&] { return !controls_.empty() || woken_; });
  if (controls_.empty()) return false;
  *control = std::move(controls_.front());
  controls_.pop_front();
  return true;
}

bool ReplayInbox::AddProbe(const v1::ProbeReport& report) {
  if (reports_ >= max_reports_) return false;
  ++reports_;
  buffered_.push_back(report);
  if (answered_seq_.exchange(report.seq()) != report.seq()) arrived_.notify_all();
  if (buffered_.size() >= kFlushReports) Flush();
  return true;
}

void ReplayInbox::Flush() {
  if (buffered_.empty()) return;
  if (!created_) {
    runs_->CreateProbeSet(set_);
    created_ = true;
  }
  runs_->AddProbeSetReports(set_.id(), buffered_);
  buffered_.clear();
}

}  // namespace mbstream

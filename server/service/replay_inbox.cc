#include "server/service/replay_inbox.h"

#include <spdlog/spdlog.h>

namespace mbstream {

ReplayInbox::ReplayInbox(RunManager* runs, v1::ProbeSet set)
    : set_(std::move(set)), recorder_(runs->replays().RecordProbeSet(set_)), one_(1) {}

ReplayInbox::~ReplayInbox() {
  recorder_->Close();
  try {
    recorder_->Flush();
  } catch (const std::exception& e) {
    spdlog::error("probe set {} of run {}: its last probe reports not stored: {}", set_.id(),
                  set_.run_id(), e.what());
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
  one_[0] = report;
  if (!recorder_->Add(one_)) return false;
  if (answered_seq_.exchange(report.seq()) != report.seq()) arrived_.notify_all();
  recorder_->FlushIfDue();
  return true;
}

}  // namespace mbstream

#include "server/runs/probe_recorder.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <exception>
#include <utility>

namespace mbstream {

ProbeRecorder::ProbeRecorder(std::string name, const RunClock& clock, Options options)
    : name_(std::move(name)), clock_(clock), options_(options) {}

void ProbeRecorder::Open(BatchWriter writer) {
  std::lock_guard<std::mutex> lock(mutex_);
  writer_ = std::move(writer);
  last_flush_ = clock_.Now();
}

bool ProbeRecorder::Add(const std::vector<v1::ProbeReport>& reports) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_ || lease_lost_ || !error_.empty() ||
        accepted_ + static_cast<int64_t>(reports.size()) > options_.max_reports) {
      return false;
    }
    for (const v1::ProbeReport& report : reports) {
      pending_.push_back(report);
      newest_seq_ = std::max(newest_seq_, report.seq());
    }
    accepted_ += static_cast<int64_t>(reports.size());
  }
  arrived_.notify_all();
  return true;
}

bool ProbeRecorder::FlushIfDue() {
  std::unique_lock<std::mutex> writing(write_mutex_, std::try_to_lock);
  if (!writing.owns_lock()) return false;  // another thread stores a batch now
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!writer_ || pending_.empty() || lease_lost_ || !error_.empty()) return false;
    const bool full = pending_.size() >= options_.batch_reports;
    if (!full) {
      if (options_.interval <= RunClock::TimePoint::duration::zero()) return false;
      const RunClock::TimePoint now = clock_.Now();
      if (now - last_flush_ < options_.interval) return false;
    }
    batch_.swap(pending_);
  }
  try {
    return Write();
  } catch (const std::exception& failure) {
    std::lock_guard<std::mutex> lock(mutex_);
    error_ = failure.what();
    if (error_.empty()) error_ = "unknown store error";
    spdlog::error("{}: {} probe reports not stored: {}", name_, batch_.size(), error_);
  }
  batch_.clear();
  return false;
}

bool ProbeRecorder::Flush() {
  std::lock_guard<std::mutex> writing(write_mutex_);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!writer_ || lease_lost_ || !error_.empty()) {
      pending_.clear();
      return !lease_lost_;
    }
    batch_.swap(pending_);
  }
  if (batch_.empty()) return true;
  struct Clear {
    std::vector<v1::ProbeReport>& batch;
    ~Clear() { batch.clear(); }
  } clear{batch_};
  return Write();
}

bool ProbeRecorder::Write() {
  const bool kept = writer_(batch_);  // writer_ is set once, before any batch (Open)
  int64_t newest = -1;
  for (const v1::ProbeReport& report : batch_) newest = std::max(newest, report.seq());
  int64_t batch_number = 0, total = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    last_flush_ = clock_.Now();
    if (!kept) {
      lease_lost_ = true;
      pending_.clear();
    } else {
      stored_ += static_cast<int64_t>(batch_.size());
      batch_number = ++batches_;
      total = stored_;
    }
  }
  if (kept) {
    spdlog::info("{}: probe batch {} stored: {} reports, {} in all, through frame {}", name_,
                 batch_number, batch_.size(), total, newest);
  } else {
    spdlog::warn("{}: {} probe reports not stored: the lease on the run was lost", name_,
                 batch_.size());
  }
  batch_.clear();
  return kept;
}

void ProbeRecorder::Close() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    closed_ = true;
  }
  arrived_.notify_all();
}

void ProbeRecorder::WaitFor(int64_t seq, std::chrono::duration<double> timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  arrived_.wait_for(lock, timeout, [&] { return newest_seq_ >= seq || closed_; });
}

int64_t ProbeRecorder::accepted() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return accepted_;
}

int64_t ProbeRecorder::stored() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stored_;
}

int64_t ProbeRecorder::batches() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return batches_;
}

bool ProbeRecorder::lease_lost() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return lease_lost_;
}

std::string ProbeRecorder::error() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return error_;
}

}  // namespace mbstream

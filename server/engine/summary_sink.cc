#include "server/engine/summary_sink.h"

#include <algorithm>
#include <cmath>

#include "server/sim/simulate.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

// Leaves the frames `kept` (ascending indices) of `result`, in order.
void KeepOnly(const std::vector<long>& kept, RunResult* result) {
  const auto compact = [&](std::vector<double>& series, size_t width) {
    if (series.empty() || width == 0) return;
    size_t to = 0;
    for (const long k : kept) {
      const size_t from = static_cast<size_t>(k) * width;
      if (from != to) std::copy_n(series.begin() + from, width, series.begin() + to);
      to += width;
    }
    series.resize(to);
  };
  const size_t n = static_cast<size_t>(result->num_dofs);
  compact(result->q, static_cast<size_t>(result->positions()));
  compact(result->qd, n);
  compact(result->tcp, 3);
  if (result->has_torques) compact(result->tau, n);
  if (result->has_energy) {
    compact(result->kinetic, 1);
    compact(result->potential, 1);
  }
  compact(result->work, 1);
  compact(result->t, 1);  // last: num_frames() counts it
}

}  // namespace

SummarySink::SummarySink(const RunConfig& config, FrameSink* inner)
    : config_(config), inner_(inner) {
  references_.resize(config.drives.size());
  for (size_t j = 0; j < config.drives.size(); ++j) {
    const DriveConfig& drive = config.drives[j];
    if (drive.kind == DriveConfig::Kind::kPdServo || drive.kind == DriveConfig::Kind::kPrescribed) {
      references_[j].emplace(drive.trajectory);
    }
  }
  summary_.keep = FrameKeepName(config.keep);
  if (config.keep.mode != FrameKeep::Mode::kAll) {  // no allocation as the frames come
    kept_.reserve(static_cast<size_t>(
        KeptFrameCount(config.keep, OutputFrameCount(config.duration, config.output_interval))));
  }
}

void SummarySink::StartSummary(const RunResult& result) {
  const size_t n = static_cast<size_t>(result.num_dofs);
  summary_.q_final.assign(static_cast<size_t>(result.positions()), 0.0);
  summary_.qd_final.assign(n, 0.0);
  summary_.joints.assign(n, JointSummary{});
  effort_square_sum_.assign(n, 0.0);
  for (size_t j = 0; j < n; ++j) {
    if (result.has_torques) summary_.joints[j].effort_peak = 0.0;
    if (Tracks(result, j)) summary_.joints[j].tracking_error_max = 0.0;
  }
}

bool SummarySink::Tracks(const RunResult& result, size_t j) const {
  // A driven one-coordinate joint. A free or ball joint's velocity coordinate (position_index
  // -1) has no position of its own: its reference, when its pose is prescribed, is a
  // component of the pose (Drive.Pose), not a coordinate.
  return j < references_.size() && references_[j] &&
         (result.num_positions == 0 || result.position_index[j] >= 0);
}

void SummarySink::AddToSummary(const RunResult& result, int frame) {
  if (computed_ == 0) StartSummary(result);
  const size_t n = static_cast<size_t>(result.num_dofs);
  MBSTREAM_CHECK_MSG(summary_.joints.size() == n, "a run changed its joint count");
  const size_t at = static_cast<size_t>(frame) * n;
  const size_t nq = static_cast<size_t>(result.positions());
  const size_t q_at = static_cast<size_t>(frame) * nq;
  const double t = result.t[static_cast<size_t>(frame)];
  summary_.t_final = t;
  std::copy_n(result.q.begin() + q_at, nq, summary_.q_final.begin());
  std::copy_n(result.qd.begin() + at, n, summary_.qd_final.begin());
  for (size_t j = 0; j < n; ++j) {
    JointSummary& joint = summary_.joints[j];
    if (result.has_torques) {
      const double effort = result.tau[at + j];
      joint.effort_peak = std::max(joint.effort_peak, std::abs(effort));
      effort_square_sum_[j] += effort * effort;
    }
    if (Tracks(result, j)) {
      const size_t position =
          result.num_positions > 0 ? static_cast<size_t>(result.position_index[j]) : j;
      const double error = std::abs(references_[j]->At(t).q - result.q[q_at + position]);
      joint.tracking_error_max = std::max(joint.tracking_error_max, error);
    }
  }
}

void SummarySink::OnFrame(const RunResult& result, int frame) {
  AddToSummary(result, frame);
  const long k = computed_++;
  if (!config_.keep.Keeps(k)) return;
  if (!KeepsFrames() && config_.keep.mode != FrameKeep::Mode::kAll) kept_.push_back(k);
  ++passed_;
  last_passed_ = k;
  if (inner_ != nullptr) inner_->OnFrame(result, frame);
}

void SummarySink::Finish(RunResult* result) {
  const long last = computed_ - 1;
  if (last >= 0 && config_.keep.KeepsLast() && last_passed_ != last) {
    if (!KeepsFrames()) kept_.push_back(last);
    ++passed_;
    last_passed_ = last;
    if (inner_ != nullptr) inner_->OnFrame(*result, result->num_frames() - 1);
  }
  summary_.frames_computed = computed_;
  summary_.frames_kept = passed_;
  for (size_t j = 0; j < summary_.joints.size() && computed_ > 0; ++j) {
    if (summary_.joints[j].effort_peak >= 0.0) {
      summary_.joints[j].effort_rms = std::sqrt(effort_square_sum_[j] / computed_);
    }
  }
  result->stats.summary = summary_;
  if (!KeepsFrames() && config_.keep.mode != FrameKeep::Mode::kAll) KeepOnly(kept_, result);
}

}  // namespace mbstream

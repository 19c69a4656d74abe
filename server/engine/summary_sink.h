// Between a run and its caller's sink: sees every output frame, keeps the run's summary of
// them (RunStats::summary: final state, peak and RMS effort and tracking error per joint)
// and passes on only the frames the run keeps (RunConfig::keep). The engine puts one in
// front of every run, so the store, the wire and the results files get the kept frames and
// the summary holds over all of them.
#pragma once

#include <optional>
#include <vector>

#include "server/drives/trajectory.h"
#include "server/sim/run_config.h"
#include "server/sim/run_result.h"

namespace mbstream {

class SummarySink : public FrameSink {
 public:
  // `inner` (may be null) gets the kept frames; `config` must outlive this.
  SummarySink(const RunConfig& config, FrameSink* inner);

  void OnFrame(const RunResult& result, int frame) override;
  bool KeepsFrames() const override { return inner_ != nullptr && inner_->KeepsFrames(); }

  // After the run: passes the last good frame on if `keep` wants it and has not had it, writes
  // the summary into result->stats.summary and, unless the inner sink keeps the frames
  // itself, leaves in `result` only the kept frames.
  void Finish(RunResult* result);

 private:
  // Whether joint (velocity coordinate) j has a tracking error: see the definition.
  bool Tracks(const RunResult& result, size_t j) const;
  void StartSummary(const RunResult& result);
  void AddToSummary(const RunResult& result, int frame);

  const RunConfig& config_;
  FrameSink* inner_;
  std::vector<std::optional<TrajectoryEvaluator>> references_;  // per drive with a motion
  std::vector<long> kept_;  // computed frames' indices kept (when `result` keeps them all)
  long computed_ = 0;       // frames seen
  long passed_ = 0;         // frames passed on
  long last_passed_ = -1;   // index among the computed of the last passed on
  std::vector<double> effort_square_sum_;
  RunSummary summary_;
};

}  // namespace mbstream

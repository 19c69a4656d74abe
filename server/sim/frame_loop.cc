#include "server/sim/frame_loop.h"

#include "server/model/ball_joint.h"
#include "server/sim/run_stop.h"

namespace mbstream {

namespace {

const double* LatestQ(const RunResult& result) {
  return result.q.data() + static_cast<size_t>(result.num_frames() - 1) * result.positions();
}

// A ball joint of the tree within `margin` of its gimbal lock at the latest recorded frame.
std::optional<std::string> GimbalLockAtLatest(const Model& model, const RunResult& result,
                                              double margin) {
  if (model.ball_joints.empty() || result.num_frames() == 0) return std::nullopt;
  return GimbalLockMessage(model, LatestQ(result), result.t.back(), margin);
}

// How near the lock (rad) the last frame of a run that failed to advance must be for the
// failure to be put down to it: 10 degrees.
constexpr double kNearLockRad = kGimbalWarningRad;

void RunFrameLoop(const std::vector<double>& times, FrameSource& source, FrameRecorder& recorder,
                  RunResult& result, FrameSink* sink, const std::atomic<bool>* cancel,
                  GimbalWatch& gimbal) {
  for (size_t k = 0; k < times.size(); ++k) {
    if (cancel && cancel->load(std::memory_order_relaxed)) {
      StopCancelled(&result.stats);
      return;
    }
    if (!source.Advance(times, k, &result.stats)) {
      if (const auto near = GimbalLockAtLatest(recorder.model(), result, kNearLockRad)) {
        result.stats.message += "; at the last frame " + *near;
      }
      return;
    }
    if (!source.Record(times[k], recorder)) {
      StopRun(&result.stats, RunStatus::kDiverged, source.NonFiniteMessage(times[k]));
      return;
    }
    if (sink) sink->OnFrame(result, result.num_frames() - 1);
    if (recorder.model().ball_joints.empty()) continue;
    if (const auto lock = gimbal.Check(LatestQ(result), times[k])) {
      StopRun(&result.stats, RunStatus::kFailed, *lock);
      return;
    }
  }
}

}  // namespace

void RunFrames(const std::vector<double>& times, FrameSource& source, FrameRecorder& recorder,
               RunResult& result, FrameSink* sink, const std::atomic<bool>* cancel) {
  GimbalWatch gimbal(recorder.model());
  RunFrameLoop(times, source, recorder, result, sink, cancel, gimbal);
  if (result.stats.status == RunStatus::kFinished) {
    if (const auto near = gimbal.NearWarning()) result.stats.warnings.push_back(*near);
  }
}

}  // namespace mbstream

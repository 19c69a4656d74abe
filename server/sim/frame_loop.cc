#include "server/sim/frame_loop.h"

#include "server/sim/run_stop.h"

namespace mbstream {

void RunFrames(const std::vector<double>& times, FrameSource& source, FrameRecorder& recorder,
               RunResult& result, FrameSink* sink, const std::atomic<bool>* cancel) {
  for (size_t k = 0; k < times.size(); ++k) {
    if (cancel && cancel->load(std::memory_order_relaxed)) {
      StopCancelled(&result.stats);
      return;
    }
    if (!source.Advance(times, k, &result.stats)) return;
    if (!source.Record(times[k], recorder)) {
      StopRun(&result.stats, RunStatus::kDiverged, source.NonFiniteMessage(times[k]));
      return;
    }
    if (sink) sink->OnFrame(result, result.num_frames() - 1);
  }
}

}  // namespace mbstream

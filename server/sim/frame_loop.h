// The one frame loop of every formulation: before each output frame it checks for
// cancellation, brings the formulation's state to the frame's time, records the frame and
// hands it to the sink. A formulation says only how to advance and how to read a frame.
#pragma once

#include <atomic>
#include <string>
#include <vector>

#include "server/sim/frame_recorder.h"
#include "server/sim/run_result.h"

namespace mbstream {

// A formulation's state as the frame loop drives it.
class FrameSource {
 public:
  virtual ~FrameSource() = default;

  // Brings the state to times[k] (k = 0: the initial state, already there). Returns false,
  // with the status and message in `stats`, when the run must stop before frame k.
  virtual bool Advance(const std::vector<double>& times, size_t k, RunStats* stats) = 0;

  // Records the frame at time t in `recorder`; false when a value is not finite.
  virtual bool Record(double t, FrameRecorder& recorder) = 0;

  // The message of a run stopped at t because its frame was not finite.
  virtual std::string NonFiniteMessage(double t) const = 0;
};

// Runs `source` over the output `times`, recording every good frame into `result` (through
// `recorder`) and passing each to `sink` if given. Stops at the first failure or when
// `cancel` is set, with the status and message in result.stats.
void RunFrames(const std::vector<double>& times, FrameSource& source, FrameRecorder& recorder,
               RunResult& result, FrameSink* sink, const std::atomic<bool>* cancel);

}  // namespace mbstream

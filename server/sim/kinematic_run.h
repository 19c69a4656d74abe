// The run of the kinematic formulation: every joint prescribed, states in closed form.
#pragma once

#include <atomic>
#include <vector>

#include "server/drives/drive_set.h"
#include "server/model/model.h"
#include "server/sim/frame_recorder.h"
#include "server/sim/run_config.h"
#include "server/sim/run_result.h"

namespace mbstream {

// Evaluates the prescribed motion (and, with config.want_torques, the drive efforts by
// RNEA) at each of `times` and records the frames.
void RunKinematic(const Model& model, const RunConfig& config, const DriveSet& drives,
                  const std::vector<double>& times, FrameRecorder& recorder, RunResult& result,
                  FrameSink* sink, const std::atomic<bool>* cancel);

}  // namespace mbstream

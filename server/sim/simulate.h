// Runs a simulation in-process: the engine behind `mbstream simulate` and the server.
#pragma once

#include <atomic>

#include "server/model/model.h"
#include "server/sim/run_config.h"
#include "server/sim/run_result.h"

namespace mbstream {

// Simulates `model` under `config` (validated by server/spec) and returns every good frame
// with statistics. Numerical failure is a status, not an exception: the result then holds
// every frame up to the last good time. Throws InputError only for a request that cannot
// start, which ValidateRun (run_validation.h) refuses before any integration. `sink`, if given,
// sees each frame as it is produced; `cancel`, if given and set, stops the run (status kCancelled).
RunResult Simulate(const Model& model, const RunConfig& config, FrameSink* sink = nullptr,
                   const std::atomic<bool>* cancel = nullptr);

// How many output frames a run of `duration` s with a frame every `interval` s has: one at
// each multiple of the interval from 0, and one at `duration` when it is not a multiple.
long OutputFrameCount(double duration, double interval);

}  // namespace mbstream

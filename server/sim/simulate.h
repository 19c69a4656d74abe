// A tree mechanism's run with the method and tolerances its config gives: the engine's inner
// entry. Callers outside the engine use Simulate (server/engine/engine.h), which honours an
// accuracy target and closed loops too and comes here for the rest.
#pragma once

#include <atomic>

#include "server/model/model.h"
#include "server/sim/control_law.h"
#include "server/sim/run_config.h"
#include "server/sim/run_prefix.h"
#include "server/sim/run_result.h"

namespace mbstream {

// Simulates `model` under `config` (accepted by ValidateRun, run_validation.h; with no
// accuracy target: config.target is ignored here) and returns every good frame with
// statistics. Numerical failure is a status, not an exception: the result then holds every
// frame up to the last good time. A config that skipped ValidateRun fails a CHECK. `sink`, if
// given, sees each frame as it is produced; `cancel`, if given and set, stops the run (status
// kCancelled); `pilot`: a pilot's frames and integration to go on from (run_prefix.h);
// `control`: the controller of the run's external drives (control_law.h), if any.
RunResult SimulateTree(const Model& model, const RunConfig& config, FrameSink* sink = nullptr,
                       const std::atomic<bool>* cancel = nullptr, const PilotLink& pilot = {},
                       ControlLaw* control = nullptr);

// How many output frames a run of `duration` s with a frame every `interval` s has: one at
// each multiple of the interval from 0, and one at `duration` when it is not a multiple.
long OutputFrameCount(double duration, double interval);

}  // namespace mbstream

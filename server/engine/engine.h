// The engine's one entry, behind `mbstream simulate` and the server's runs: Simulate honours
// every field of a RunConfig. A run with an accuracy target has its method and tolerances
// chosen, runs and is verified (server/choose/target_run.h); a mechanism with closed loops
// runs with its loops as constraints (server/sim/loop_run.h); any other run integrates with
// the method and tolerances it gives (server/sim/simulate.h). Which of them applies is this
// function's business, not its caller's.
#pragma once

#include <atomic>
#include <vector>

#include "server/model/loop_closure.h"
#include "server/model/model.h"
#include "server/sim/control_law.h"
#include "server/sim/run_config.h"
#include "server/sim/run_result.h"

namespace mbstream {

// Simulates `model`, with the joints cut from it to make it a tree (`loops`, none for a
// tree), under `config` and returns every good frame with statistics. `config` must have
// passed ValidateLoopRun (server/sim/loop_run.h; ValidateRun for a tree) once, at the door:
// the service on StartRun, the CLI after reading the spec. The engine does not validate it
// again; what it relies on it CHECKs (InternalError: a bug of the caller). Numerical failure is
// a status, not an exception: the result then holds every frame up to the last good time.
// `sink`, if given, sees each frame as it is produced; `cancel`, if given and set, stops the
// run (status kCancelled). `control` commands the run's external drives at each control
// instant (control_law.h; a run with external drives and no controller fails).
RunResult Simulate(const Model& model, const std::vector<LoopClosure>& loops,
                   const RunConfig& config, FrameSink* sink = nullptr,
                   const std::atomic<bool>* cancel = nullptr, ControlLaw* control = nullptr);

// The same for a tree (no loops).
RunResult Simulate(const Model& model, const RunConfig& config, FrameSink* sink = nullptr,
                   const std::atomic<bool>* cancel = nullptr);

}  // namespace mbstream

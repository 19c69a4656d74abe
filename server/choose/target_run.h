// A run with an accuracy target, end to end: the choice (method_choice.h), the run itself
// (frames streamed to the sink as usual), and its verification (verification.h). The
// reasoning and the check go into RunStats::choice_json and RunStats::target_met; a missed
// target leaves the run FINISHED with target_met false and a message naming what to change.
#pragma once

#include <atomic>

#include "server/choose/method_choice.h"
#include "server/choose/verification.h"
#include "server/model/model.h"
#include "server/sim/run_config.h"
#include "server/sim/run_result.h"

namespace mbstream {

// The end of every target run: the verification's verdict, the choice's JSON and the
// message of a missed or unverified target into `result`'s stats.
void FinishTargetRun(const RunConfig& config, const MethodChoice& choice,
                     const Verification& verification, RunResult* result);

// Chooses, runs and verifies `config` (config.target set, ValidateRun accepted it). The
// engine's entry (server/engine/engine.h) comes here for a run with a target.
RunResult RunWithTarget(const Model& model, const RunConfig& config, FrameSink* sink = nullptr,
                        const std::atomic<bool>* cancel = nullptr);

}  // namespace mbstream

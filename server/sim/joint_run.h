// The run of the joint formulation: the joint-space ODE (2n states) with an ODE method.
#pragma once

#include <atomic>
#include <vector>

#include "server/drives/drive_set.h"
#include "server/model/model.h"
#include "server/sim/control_law.h"
#include "server/sim/frame_recorder.h"
#include "server/sim/run_budget.h"
#include "server/sim/run_config.h"
#include "server/sim/run_prefix.h"
#include "server/sim/run_result.h"

namespace mbstream {

// Integrates the joint-space ODE over `times` and records every good frame; sets the
// result's equations, Jacobian non-zeros and solver statistics. Stops at
// budget->cpu_deadline_s and fills budget's stop fields when the budget runs out. Goes on
// from pilot.prefix where it fits; hands its integration on with pilot.keep_integration.
// With sampled drives: RunSampledJointSpace (sampled_joint_run.h), commanded by `control`.
void RunJointSpace(const Model& model, const RunConfig& config, const PilotLink& pilot,
                   const DriveSet& drives, const std::vector<double>& times,
                   FrameRecorder& recorder, RunResult& result, FrameSink* sink,
                   const std::atomic<bool>* cancel, BudgetTracking* budget,
                   ControlLaw* control = nullptr);

}  // namespace mbstream

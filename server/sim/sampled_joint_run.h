// The joint formulation's run with sampled drives (drive_set.h: external drives, pd_servos
// with a period): the joint-space ODE integrated period by period. At each control instant
// t_k = k h the sampled servos' laws are evaluated at the state then, the controller
// (control_law.h) gives the external joints' commands, and the integrator starts afresh at
// (t_k, y(t_k)) with them held: a new command is a discontinuity, which no step may straddle.
// The integrator is made once and restarted at each instant in its own memory
// (Integrator::Restart): after the first period a period allocates nothing.
#pragma once

#include <atomic>
#include <vector>

#include "server/drives/drive_set.h"
#include "server/model/model.h"
#include "server/sim/control_law.h"
#include "server/sim/frame_recorder.h"
#include "server/sim/run_budget.h"
#include "server/sim/run_config.h"
#include "server/sim/run_result.h"

namespace mbstream {

// RunJointSpace for drives.any_sampled() (no free bodies, no prefix: ValidateRun). A run with
// external drives and no `control` fails at its first control instant.
void RunSampledJointSpace(const Model& model, const RunConfig& config, const DriveSet& drives,
                          const std::vector<double>& times, FrameRecorder& recorder,
                          RunResult& result, FrameSink* sink, const std::atomic<bool>* cancel,
                          BudgetTracking* budget, ControlLaw* control);

}  // namespace mbstream

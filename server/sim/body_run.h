// The run loop of the body-coordinate formulations (body-index3, body-index2 with IDA;
// body-baumgarte with an ODE method).
#pragma once

#include <atomic>
#include <vector>

#include <Eigen/Core>

#include "server/drives/drive_set.h"
#include "server/model/loop_closure.h"
#include "server/model/model.h"
#include "server/sim/frame_recorder.h"
#include "server/sim/run_budget.h"
#include "server/sim/run_config.h"
#include "server/sim/run_result.h"

namespace mbstream {

bool IsBodyFormulation(Formulation formulation);

// A mechanism with closed loops: its cut joints (more joints between two bodies: body_cuts.h)
// and its assembled initial joint state (loop_plan.h), which replaces the config's.
struct BodyLoops {
  const std::vector<LoopClosure>& loops;
  const Eigen::VectorXd& q0;
  const Eigen::VectorXd& qd0;
  // When given (RunConfig::want_loop_forces): filled with the cut joints' reactions
  // (BodyReadout::CutReactions) before each frame is recorded.
  Eigen::VectorXd* reactions = nullptr;
};

// Integrates `model` in body coordinates over `times` and records every good frame; sets
// the result's equations, Jacobian non-zeros, solver statistics, status and constraint
// drift. Stops at budget->cpu_deadline_s and fills budget's stop fields when the budget
// runs out. Throws InputError for a model the body formulations do not handle.
void RunBody(const Model& model, const RunConfig& config, Formulation formulation,
             const DriveSet& drives, const std::vector<double>& times, FrameRecorder& recorder,
             RunResult& result, FrameSink* sink, const std::atomic<bool>* cancel,
             BudgetTracking* budget, const BodyLoops* loops = nullptr);

}  // namespace mbstream

// Runs a mechanism with closed loops in-process: SimulateTree's counterpart for a Model and the
// joints cut from it (server/model/loop_closure.h). Formulations: kinematic (every degree
// of freedom prescribed: Newton on the loops at each frame, nothing integrated) and joint
// (the loops as constraints with Baumgarte stabilisation, projected after each step of
// CVODE BDF: closed_loop_ode.h; with method ida the index-2 GGL DAE, closed_loop_dae.h) and
// the body formulations (the cut joints as more joints between bodies: body_run.h). Every run
// reports the largest constraint residuals over its frames (RunStats' drift figures: m, rad, m/s or
// rad/s) and how the loops were closed (RunStats::loops). The tree may hold free bodies and
// ball joints (kinematic and joint with an ODE method: q on its manifold, the loops in velocity
// space); method ida and the body formulations refuse them, naming the joint.
#pragma once

#include <atomic>
#include <vector>

#include "server/model/loop_closure.h"
#include "server/model/model.h"
#include "server/sim/formulation_choice.h"
#include "server/sim/run_config.h"
#include "server/sim/run_result.h"

namespace mbstream {

// Validates the run (ValidateRun's checks of the tree and the run, then PlanLoopRun's) and
// returns its formulation. Throws InputError saying what to change.
FormulationChoice ValidateLoopRun(const Model& model, const std::vector<LoopClosure>& loops,
                                  const RunConfig& config);

// As SimulateTree (simulate.h), for a config ValidateLoopRun accepted (the engine's entry,
// server/engine/engine.h, comes here for a model with loops): numerical failure is a status.
// With no loops it is SimulateTree.
RunResult SimulateLoops(const Model& model, const std::vector<LoopClosure>& loops,
                        const RunConfig& config, FrameSink* sink = nullptr,
                        const std::atomic<bool>* cancel = nullptr);

}  // namespace mbstream

// A run with an accuracy target of a mechanism with closed loops (RunWithTarget's counterpart
// for SimulateLoops). Every degree of freedom prescribed: the kinematic formulation, exact
// by construction. Otherwise the candidates are the loop path's integrators, BDF with
// projection and IDA on the index-2 GGL DAE (or the one method given), each piloted through
// SimulateLoops over the whole run at three tolerances (a thousandth of the tightest target,
// and 10 and 100 times below): a linkage released at rest barely moves over the tree path's
// 5 % pilot, and no stiffness probe sees the constrained motion (it would see the tree
// without its loops). The error is fitted as a power of the tolerance; the cheapest candidate
// predicted to meet the target runs, and a tighter run of the mechanism verifies it
// (verification.h).
#pragma once

#include <atomic>
#include <vector>

#include "server/model/loop_closure.h"
#include "server/model/model.h"
#include "server/sim/run_config.h"
#include "server/sim/run_result.h"

namespace mbstream {

// The tightest tolerance of a loop run with a target (atol = rtol / 100): the projection's
// Newton tolerance is a hundredth of atol, and towards round-off it struggles (the passive
// slider-crank took 15 s of CPU at rtol 1e-11 against 0.05 s at 1e-10; below atol 1e-13 it
// fails: closed_loop_ode.h, docs/closed_loops.md).
constexpr double kLoopMinRtol = 1e-10;

// Chooses, runs and verifies `config` (config.target set; ValidateLoopRun accepted it).
RunResult RunLoopsWithTarget(const Model& model, const std::vector<LoopClosure>& loops,
                             const RunConfig& config, FrameSink* sink = nullptr,
                             const std::atomic<bool>* cancel = nullptr);

}  // namespace mbstream

// The pilot of a candidate: two short runs over the first part of the run at two tolerances,
// 100 times apart. The looser run's distance from the tighter one is its error; the error
// is taken proportional to the tolerance, grown from the pilot span to the whole run linearly
// in time or, where nearby solutions separate, exponentially;
// the steps follow rtol^-beta with beta from the two runs (at least the method's order allows),
// at the tighter run's right-hand sides per step.
#pragma once

#include <atomic>

#include "server/choose/candidate.h"
#include "server/model/model.h"
#include "server/sim/run_result.h"

namespace mbstream {

// Smallest and largest tolerance a choice uses: below 1e-13 round-off dominates the local
// error of every method here (docs/accuracy.md, the reference floors).
constexpr double kMinRtol = 1e-13;
constexpr double kMaxRtol = 1e-3;
// The run aims this far below the target; its check this far below it. The check's own error
// (predicted at a tenth of the target) is counted against the run: the target is met when the
// run's distance from its check plus that tenth stays within it (verification.h). A check
// predicted at 3 % (a tolerance 10 times tighter than the run's) cost 1.3-1.5 runs of BDF on
// the reference scenes; at 10 % (3 times tighter) 1.1-1.2.
constexpr double kRunSafety = 0.3;
constexpr double kCheckSafety = 0.1;

struct PilotSpan {
  double span_s = 0.0;      // s, the pilot's simulated time
  double interval_s = 0.0;  // s between its output frames
};

// The pilots' looser tolerance: the tightest target, within what pilots resolve (the tighter
// pilot is 100 times below it, and no tighter than `min_rtol`).
double PilotRtol(const AccuracyTarget& target, double min_rtol = kMinRtol);

// 5 % of the run, at least two output frames of it, rounded up to whole output intervals, at
// most the whole run.
PilotSpan PilotSpanFor(const RunConfig& config);

// Runs the pilot of `candidate` at rtol[0] = `rtol` (the run's configuration `config`, with
// the joint formulation, cut to the span) and fills its pilot fields; returns the tighter
// pilot's result (its states serve the stiffness probe). A failed pilot leaves the candidate
// unusable, with the reason in its verdict.
RunResult RunPilot(const Model& model, const RunConfig& config, const PilotSpan& span, double rtol,
                   Candidate* candidate, const std::atomic<bool>* cancel);

// Fills the run's and the check's tolerances and predicted CPU times of a usable candidate
// for `target` over the whole run of `duration` s; `separation_rate` (1/s, >= 0): how fast
// nearby solutions separate (StiffnessProbe::separation_rate); `rhs_cost_s`: s of CPU per
// right-hand side (StiffnessProbe::rhs_cost_s).
void PredictCandidate(const AccuracyTarget& target, double duration, const PilotSpan& span,
                      double separation_rate, double rhs_cost_s, Candidate* candidate);

}  // namespace mbstream

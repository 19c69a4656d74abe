// One integrator the method choice considers, what its pilot runs measured, and the fitted
// relations that predict its error and cost at any tolerance over the whole run.
#pragma once

#include <memory>
#include <string>

#include "server/integrate/method.h"
#include "server/sim/run_config.h"
#include "server/sim/run_prefix.h"

namespace mbstream {

// Errors by criterion of the accuracy target; < 0 = not measured.
struct ErrorFigures {
  double tcp_m = -1.0;
  double joint_rad = -1.0;
  double energy_rel = -1.0;
};

struct Candidate {
  std::string name;  // "bdf", "adams", "erk", "erk-verner", "dirk"
  Method method = Method::kBdf;
  std::string table;             // ARKODE table name for erk ("" = default)
  double stability_reach = 0.0;  // explicit methods: stable for h |lambda| below this
  double rhs_per_step = 1.0;     // explicit methods: right-hand sides per step
  // The least exponent beta of steps ~ rtol^-beta: with local error ~ h^(p+1) at its
  // highest order p (the error estimate's order for an embedded pair), a step can grow no
  // faster than rtol^(1/(p+1)). A pilot's own fit is smaller where its few steps are mostly
  // the start-up (BDF and Adams start at order 1 with tiny steps), so the larger of the two.
  double min_steps_exponent = 0.0;

  bool piloted = false;
  bool usable = false;  // piloted, both pilots finished, the fit is defined
  std::string verdict;  // why it was excluded or not piloted ("" when usable)

  // The pilot: two runs over [0, pilot span] at rtol[0] and rtol[1] = rtol[0] / 100.
  double rtol[2] = {0.0, 0.0};
  long steps[2] = {0, 0};
  long rhs_evals[2] = {0, 0};
  double cpu_s[2] = {0.0, 0.0};
  ErrorFigures error;           // at rtol[0] over the pilot span (tcp, joint: against rtol[1])
  ErrorFigures growth;          // factor from the pilot span to the whole run, per criterion
  double steps_exponent = 0.0;  // steps ~ rtol^-steps_exponent
  // s of CPU per step: the tighter pilot's right-hand sides per step (the Newton iterations
  // and finite-difference Jacobians included) at the probe's CPU per right-hand side. (The
  // pilots' own CPU per step is mostly their start-up: a few dozen steps against a set-up
  // that costs as much as a hundred.)
  double cpu_per_step_s = 0.0;
  // The pilots' frames, each with its integration still alive at the span's end: the run or
  // check of this candidate at a tolerance no tighter than a pilot's takes the tighter such
  // pilot over (PilotLink::prefix, run_prefix.h) instead of integrating the span again.
  std::shared_ptr<const RunPrefix> pilots[2];

  // Predictions for the run (rtol_for) and its check (check_rtol), at their tolerances.
  double explicit_cpu_floor_s = -1.0;  // explicit: the CPU stability alone needs
  double run_rtol = 0.0, run_cpu_s = -1.0;
  double check_rtol = 0.0, check_cpu_s = -1.0;
  bool resolvable = true;  // the target is reachable above the smallest tolerance
};

// erk with its default table is "erk"; with table "verner" "erk-verner".
Candidate MakeCandidate(Method method, const std::string& table = "");

// The run's configuration with this candidate's method and tolerance (atol = rtol / 100),
// with no target.
RunConfig WithCandidate(RunConfig config, const Candidate& candidate, double rtol);

// The pilot a run of this candidate at `rtol` goes on from: the loosest of the candidate's
// pilots that is at least as tight as `rtol` and whose integration no run has taken yet (null
// when there is none: the run starts at t = 0). The run takes the looser pilot where it can,
// which leaves the tighter one to its check.
std::shared_ptr<const RunPrefix> PilotToContinue(const Candidate& candidate, double rtol);

}  // namespace mbstream

// The choice of formulation, method and tolerance for an accuracy target, from what can be
// learnt cheaply before the run: whether every joint is prescribed (closed form), the
// stiffness (largest eigenvalue magnitude of the joint-space Jacobian at the initial state and
// at sampled pilot states, against the step an explicit method could take), a pilot of each
// candidate at two tolerances (error against tolerance, steps against tolerance, CPU per
// step), and the predicted CPU time of the whole run. Physics only: no wire types.
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "server/choose/candidate.h"
#include "server/choose/pilot.h"
#include "server/choose/stiffness_probe.h"
#include "server/model/model.h"
#include "server/sim/run_config.h"

namespace mbstream {

struct MethodChoice {
  RunConfig run;  // what runs: formulation, method, table, tolerances; no target
  // The pilot the run goes on from (null: from t = 0), beside `run` (run_prefix.h).
  std::shared_ptr<const RunPrefix> continues;
  std::string formulation;  // "kinematic" or "joint"
  std::string formulation_reason;
  bool closed_form = false;  // kinematic: exact, nothing chosen beyond it
  PilotSpan pilot;
  StiffnessProbe stiffness;
  double bdf_mean_step_s = 0.0;  // s, BDF's mean step in its looser pilot
  // 1/s, the error growth rate the predictions used: 0 when every joint is on a servo or
  // prescribed, else 0.75 x the Jacobian's largest real part.
  double separation_rate_used = 0.0;
  std::vector<Candidate> candidates;
  int pick = -1;           // index into candidates (-1: closed form)
  int check = -1;          // the candidate of the verification run
  bool resolvable = true;  // false: even kMinRtol is predicted to miss the target
  std::string reason;      // one sentence: why this pick
  double cpu_s = 0.0;      // s of CPU the choice took (pilots and probes)
};

// Chooses for `config` (config.target set; method_auto, or a method whose tolerance alone is
// chosen), a config ValidateRun accepted (a CHECK fails otherwise).
MethodChoice ChooseMethod(const Model& model, const RunConfig& config,
                          const std::atomic<bool>* cancel = nullptr);

}  // namespace mbstream

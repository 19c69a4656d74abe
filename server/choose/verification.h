// The check after a target run: an independent estimate of the error it achieved, from a run
// of the cheapest candidate at a tolerance about 3 times tighter (predicted error 10 % of the
// target; pilot.h, kCheckSafety), compared on the output frames; the target is met when that
// distance plus the check's predicted error stays within it. Measured, never assumed;
// budgeted (10 times its predicted CPU time, at least 1 s); skipped with RunConfig::verify
// false.
#pragma once

#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "server/choose/candidate.h"
#include "server/choose/frame_track.h"
#include "server/choose/method_choice.h"
#include "server/model/loop_closure.h"
#include "server/model/model.h"
#include "server/sim/run_result.h"

namespace mbstream {

struct Verification {
  bool ran = false;
  std::string how;    // "closed form: ...", "erk-verner at rtol 1e-12 ...", "skipped: ..."
  double rtol = 0.0;  // the check's tolerance
  double budget_cpu_s = 0.0;
  double cpu_s = 0.0;  // s of CPU the check took
  // The check continued a pilot from this time (s; 0: from the start), that pilot's frames.
  double continued_from_s = 0.0;
  std::shared_ptr<const RunPrefix> prefix;
  ErrorFigures achieved;    // the run's error estimates (< 0: not measured)
  std::optional<bool> met;  // empty: not verified
  double horizon_s = -1.0;  // missed: up to when the run and its check agree within the target
  std::string message;      // missed or not verified: what happened and what to change
};

// Verifies `run` (its frames in `track`) against `asked`, the run's configuration with its
// target, as chosen by `choice`. With `loops` (the joints cut from the model's loops) the
// check is a run of the mechanism (SimulateLoops), which goes on from no pilot.
Verification VerifyTarget(const Model& model, const RunConfig& asked, const MethodChoice& choice,
                          const RunResult& run, const FrameTrack& track,
                          const std::atomic<bool>* cancel,
                          const std::vector<LoopClosure>& loops = {});

}  // namespace mbstream

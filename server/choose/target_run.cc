#include "server/choose/target_run.h"

#include "server/choose/choice_json.h"
#include "server/choose/frame_track.h"
#include "server/choose/method_choice.h"
#include "server/choose/verification.h"
#include "server/sim/simulate.h"
#include "shared/common/check.h"

namespace mbstream {

void FinishTargetRun(const RunConfig& config, const MethodChoice& choice,
                     const Verification& verification, RunResult* result) {
  RunStats& stats = result->stats;
  stats.target_met = verification.met;
  stats.choice_json = ChoiceJson(config, choice, verification, stats);
  if (stats.status == RunStatus::kFinished && !verification.message.empty()) {
    stats.message = verification.message;
  }
  if (stats.status == RunStatus::kFinished && !choice.resolvable && verification.met != true) {
    stats.message =
        "choice: " + choice.reason + (stats.message.empty() ? "" : "; " + stats.message);
  }
}

RunResult RunWithTarget(const Model& model, const RunConfig& config, FrameSink* sink,
                        const std::atomic<bool>* cancel) {
  MBSTREAM_CHECK_MSG(config.target.any(), "a run without a target runs with SimulateTree");
  const MethodChoice choice = ChooseMethod(model, config, cancel);
  TrackingSink tracking(sink);
  RunResult result =
      SimulateTree(model, choice.run, &tracking, cancel, PilotLink{choice.continues});
  const Verification verification =
      VerifyTarget(model, config, choice, result, tracking.track(), cancel);
  FinishTargetRun(config, choice, verification, &result);
  return result;
}

}  // namespace mbstream

#include "server/choose/verification.h"

#include <algorithm>

#include "server/choose/pilot.h"
#include "server/sim/loop_run.h"
#include "server/sim/simulate.h"
#include "shared/common/format.h"

namespace mbstream {

namespace {

std::string Pretty(double value) { return FormatString("%.3g", value); }

// Which asked criteria the achieved errors miss, as "TCP error 3e-5 m > target 1e-5 m; ...",
// and the worst ratio achieved / target. The TCP and joint figures are distances from the
// check, whose own error (predicted at kCheckSafety x the target) is added to them; the
// energy figure is the run's own balance.
std::string Misses(const AccuracyTarget& target, const ErrorFigures& achieved, double* worst) {
  std::string misses;
  *worst = 0.0;
  auto check = [&](double asked, double value, double allowance, const char* what,
                   const char* unit) {
    if (!(asked > 0.0) || value < 0.0) return;
    const double bound = value + allowance * asked;
    *worst = std::max(*worst, bound / asked);
    if (bound <= asked) return;
    misses += std::string(misses.empty() ? "" : "; ") + what + " about " + Pretty(value) + unit +
              (allowance > 0.0 ? " (+ " + Pretty(allowance * asked) + unit + " for the check's own)"
                               : std::string()) +
              " > target " + Pretty(asked) + unit;
  };
  check(target.tcp_error_m, achieved.tcp_m, kCheckSafety, "TCP error", " m");
  check(target.joint_error_rad, achieved.joint_rad, kCheckSafety, "joint error", " rad");
  check(target.energy_error_rel, achieved.energy_rel, 0.0, "energy error", "");
  return misses;
}

}  // namespace

Verification VerifyTarget(const Model& model, const RunConfig& asked, const MethodChoice& choice,
                          const RunResult& run, const FrameTrack& track,
                          const std::atomic<bool>* cancel, const std::vector<LoopClosure>& loops) {
  Verification v;
  if (run.has_energy) v.achieved.energy_rel = run.stats.energy_error_max;
  if (choice.closed_form) {
    v.how =
        "closed form: the states are the prescribed motion itself, so the TCP and joint "
        "errors are 0 by construction (nothing is integrated)";
    v.achieved.tcp_m = 0.0;
    v.achieved.joint_rad = 0.0;
    v.met = true;
    return v;
  }
  if (run.stats.status != RunStatus::kFinished) {
    v.how = "skipped: the run did not finish";
    v.message = std::string("not verified: the run ended ") + RunStatusName(run.stats.status);
    return v;
  }
  if (!asked.verify || choice.check < 0) {
    v.how = asked.verify ? "skipped: no independent check (no other candidate, and no tighter "
                           "tolerance for the run's method)"
                         : "skipped: verify is false";
    v.message = "not verified (" + v.how.substr(9) + "); the choice predicted the target " +
                (choice.resolvable ? "met" : "out of reach (see the choice's reason)");
    return v;
  }
  const Candidate& check = choice.candidates[static_cast<size_t>(choice.check)];
  v.rtol = check.check_rtol;
  v.budget_cpu_s = std::max(1.0, 10.0 * check.check_cpu_s);
  RunConfig config = WithCandidate(choice.run, check, v.rtol);
  const PilotLink pilot{PilotToContinue(check, v.rtol)};
  config.want_torques = false;
  config.max_cpu_s = v.budget_cpu_s;
  config.max_steps = 0;
  v.how = FormatString(
      "%s at rtol %.3g (predicted error %.3g x the target), compared on the %d "
      "output frames",
      check.name.c_str(), v.rtol, kCheckSafety, track.frames());
  const RunResult reference = loops.empty() ? SimulateTree(model, config, nullptr, cancel, pilot)
                                            : SimulateLoops(model, loops, config, nullptr, cancel);
  v.ran = true;
  v.cpu_s = reference.stats.cpu_s;
  v.continued_from_s = reference.stats.continued_from_s;
  v.prefix = pilot.prefix;
  if (reference.stats.status != RunStatus::kFinished) {
    v.message = FormatString(
        "not verified: the check (%s) ended %s at t = %.4g s after %.3g s of CPU (budget %.3g "
        "s); give \"verify\": false to skip it, or a looser target",
        v.how.c_str(), RunStatusName(reference.stats.status), reference.stats.t_reached, v.cpu_s,
        v.budget_cpu_s);
    return v;
  }
  const FrameTrack check_track = TrackOf(reference);
  const TrackDifference d = CompareTracks(track, check_track);
  v.achieved.tcp_m = d.tcp_m;
  v.achieved.joint_rad = d.joint_rad;
  double worst = 0.0;
  const std::string misses = Misses(asked.target, v.achieved, &worst);
  v.met = misses.empty();
  if (*v.met) return v;
  const bool tcp = asked.target.tcp_error_m > 0.0;
  v.horizon_s = AgreementHorizon(
      track, check_track, tcp ? asked.target.tcp_error_m : asked.target.joint_error_rad, tcp);
  const double rtol = std::max(kMinRtol, choice.run.rtol * kRunSafety / worst);
  v.message = "target missed: " + misses + " (against " + v.how + "); ";
  if (rtol > kMinRtol) {
    v.message += FormatString("rerun with method %s and rtol %.3g (atol %.3g)",
                              MethodName(choice.run.method), rtol, rtol / 100.0);
  } else {
    v.message += "no tolerance in double precision is predicted to reach it";
  }
  if (v.horizon_s >= 0.0 && v.horizon_s < asked.duration) {
    v.message += FormatString(
        "; the run and its check agree within the target only up to t = %.4g s of %.4g s: if "
        "the motion is chaotic, no run resolves it beyond that horizon (shorten the run or "
        "loosen the target)",
        v.horizon_s, asked.duration);
  }
  return v;
}

}  // namespace mbstream

#include "server/choose/loop_target_run.h"

#include <algorithm>
#include <cmath>

#include "server/choose/frame_track.h"
#include "server/choose/method_choice.h"
#include "server/choose/target_run.h"
#include "server/choose/verification.h"
#include "server/integrate/thread_cpu_clock.h"
#include "server/sim/loop_run.h"
#include "shared/common/check.h"
#include "shared/common/format.h"

namespace mbstream {

namespace {

struct LoopScene {
  const Model& model;
  const std::vector<LoopClosure>& loops;
  const RunConfig& config;
  const std::atomic<bool>* cancel;
};

constexpr double kTinyError = 1e-15;  // below this the pilots agree to round-off

// The fit of a candidate's error to its tolerance: error = error1 (rtol / rtol1)^order per
// criterion, from three pilots of the whole run at rtol0, rtol0 / 10 and rtol0 / 100.
struct ErrorFit {
  double rtol1 = 0.0;  // the middle pilot's
  ErrorFigures at1;    // the middle pilot's errors
  ErrorFigures order;  // d log(error) / d log(rtol), within [0.3, 1.2]
};

constexpr double kMinOrder = 0.3, kMaxOrder = 1.2;

// Distances d0, d1 of the loosest and the middle pilot from the tightest: with error = C
// rtol^p (the errors alike in direction), d0 / d1 = 10^p + 1 (the tightest pilot's own
// error, 10^-p of the middle one's, is most of what d1 misses). Returns p and sets *at1 to
// the middle pilot's own error, d1 / (1 - 10^-p).
double FitOrder(double d0, double d1, double* at1) {
  const double ratio = std::max(d0, kTinyError) / std::max(d1, kTinyError);
  const double p = std::clamp(std::log10(std::max(ratio - 1.0, 1.0)), kMinOrder, kMaxOrder);
  *at1 = d1 / (1.0 - std::pow(10.0, -p));
  return p;
}

// The three pilots of `c` over the whole run, the loosest at `rtol`; false when one fails
// (its verdict says which).
bool PilotLoops(const LoopScene& scene, double rtol, Candidate* c, ErrorFit* fit) {
  c->piloted = true;
  RunConfig pilot = scene.config;
  pilot.formulation = Formulation::kJoint;
  pilot.want_torques = false;
  pilot.max_steps = 0;
  RunResult results[3];
  for (int k = 0; k < 3; ++k) {
    const double rtol_k = std::max(kLoopMinRtol, rtol / std::pow(10.0, k));
    results[k] = SimulateLoops(scene.model, scene.loops, WithCandidate(pilot, *c, rtol_k), nullptr,
                               scene.cancel);
    const RunStats& stats = results[k].stats;
    if (stats.status != RunStatus::kFinished) {
      c->verdict =
          FormatString("its pilot at rtol %.3g ended %s at t = %.4g s: %s", rtol_k,
                       RunStatusName(stats.status), stats.t_reached, stats.message.c_str());
      return false;
    }
    if (k == 1) continue;  // the JSON's two pilots: the loosest and the tightest
    const int slot = k / 2;
    c->rtol[slot] = rtol_k;
    c->steps[slot] = stats.solver.steps;
    c->rhs_evals[slot] = stats.solver.rhs_evals;
    c->cpu_s[slot] = stats.cpu_s;
  }
  const FrameTrack tight = TrackOf(results[2]);
  const TrackDifference d0 = CompareTracks(TrackOf(results[0]), tight);
  const TrackDifference d1 = CompareTracks(TrackOf(results[1]), tight);
  c->error = {d0.tcp_m, d0.joint_rad, results[0].stats.energy_error_max};
  fit->rtol1 = rtol / 10.0;
  fit->order.tcp_m = FitOrder(d0.tcp_m, d1.tcp_m, &fit->at1.tcp_m);
  fit->order.joint_rad = FitOrder(d0.joint_rad, d1.joint_rad, &fit->at1.joint_rad);
  // the energy figure is each run's own balance, not a distance
  fit->at1.energy_rel = results[1].stats.energy_error_max;
  fit->order.energy_rel = std::clamp(std::log10(std::max(c->error.energy_rel, kTinyError) /
                                                std::max(fit->at1.energy_rel, kTinyError)),
                                     kMinOrder, kMaxOrder);
  const double step_ratio = static_cast<double>(std::max(c->steps[1], 1L)) /
                            static_cast<double>(std::max(c->steps[0], 1L));
  c->steps_exponent = std::clamp(std::log(step_ratio) / std::log(c->rtol[0] / c->rtol[1]),
                                 c->min_steps_exponent, 1.0);
  c->cpu_per_step_s = c->cpu_s[1] / static_cast<double>(std::max(c->steps[1], 1L));
  c->growth = {1.0, 1.0, 1.0};  // the pilots span the whole run
  c->usable = true;
  return true;
}

// The tolerance at which the fit predicts `fraction` of every asked criterion (not clamped
// below: under kLoopMinRtol the target is out of reach).
double RtolFor(const AccuracyTarget& target, const ErrorFit& fit, double fraction) {
  // Never looser than the loosest pilot: above it the fit is not measured (errors at
  // round-off in the pilots give an order of 0.3 and a tolerance far too loose).
  double best = 10.0 * fit.rtol1;
  auto limit = [&](double asked, double error, double order) {
    if (!(asked > 0.0)) return;
    best = std::min(
        best, fit.rtol1 * std::pow(fraction * asked / std::max(error, kTinyError), 1.0 / order));
  };
  limit(target.tcp_error_m, fit.at1.tcp_m, fit.order.tcp_m);
  limit(target.joint_error_rad, fit.at1.joint_rad, fit.order.joint_rad);
  limit(target.energy_error_rel, fit.at1.energy_rel, fit.order.energy_rel);
  return best;
}

double PredictedCpu(const Candidate& c, double rtol) {
  return static_cast<double>(std::max(c.steps[1], 1L)) *
         std::pow(c.rtol[1] / rtol, c.steps_exponent) * c.cpu_per_step_s;
}

// The run's and the check's tolerances and CPU times of a usable candidate.
void PredictLoops(const AccuracyTarget& target, const ErrorFit& fit, Candidate* c) {
  const double run = RtolFor(target, fit, kRunSafety);
  c->resolvable = run >= kLoopMinRtol;
  c->run_rtol = std::max(run, kLoopMinRtol);
  c->check_rtol = std::max(kLoopMinRtol, std::min(RtolFor(target, fit, kCheckSafety),
                                                  c->run_rtol * kCheckSafety / kRunSafety));
  // IDA on the GGL DAE is trusted down to its tightest pilot only: its Newton stopped
  // converging below rtol 1e-6 to 1e-8 on the linkages until the multipliers got tolerances
  // of their own (docs/closed_loops.md), and a tolerance beyond the pilots is not measured.
  const bool ida = c->method == Method::kIda;
  if (ida) c->resolvable = c->resolvable && c->run_rtol >= c->rtol[1];
  c->run_cpu_s = PredictedCpu(*c, c->run_rtol);
  c->check_cpu_s = ida && c->check_rtol < c->rtol[1] ? -1.0 : PredictedCpu(*c, c->check_rtol);
}

// The pilots and predictions of every candidate; the pick (cheapest predicted run that meets
// the target, else the tightest) and the check (cheapest predicted check).
void ChooseAmongCandidates(const LoopScene& scene, MethodChoice* choice) {
  const RunConfig& config = scene.config;
  choice->candidates = config.method_auto ? std::vector<Candidate>{MakeCandidate(Method::kBdf),
                                                                   MakeCandidate(Method::kIda)}
                                          : std::vector<Candidate>{MakeCandidate(config.method)};
  // Pilots of the whole run (the tree path's 5 % of a linkage released at rest sees it barely
  // move, and no stiffness probe sees the constrained motion) from a thousandth of the
  // tightest target down: the four-bar's joint error is 2,000 to 20,000 x rtol, of order 0.6
  // to 0.9 in rtol, and far from any power law at rtol 1e-5 and above (docs/accuracy.md).
  choice->pilot = PilotSpan{config.duration, config.output_interval};
  const double rtol = std::max(100.0 * kLoopMinRtol, 1e-3 * PilotRtol(config.target, 0.0));
  for (Candidate& c : choice->candidates) {
    ErrorFit fit;
    if (PilotLoops(scene, std::min(rtol, kMaxRtol), &c, &fit)) PredictLoops(config.target, fit, &c);
  }
  auto better_run = [](const Candidate& a, const Candidate& b) {
    if (a.resolvable != b.resolvable) return a.resolvable;
    return a.resolvable ? a.run_cpu_s < b.run_cpu_s : a.run_rtol > b.run_rtol;
  };
  const int n = static_cast<int>(choice->candidates.size());
  auto at = [&](int i) -> const Candidate& { return choice->candidates[static_cast<size_t>(i)]; };
  for (int i = 0; i < n; ++i) {
    if (at(i).usable && (choice->pick < 0 || better_run(at(i), at(choice->pick)))) choice->pick = i;
  }
  if (choice->pick < 0) return;
  // The check: tighter than the run (at the floor, where the run's own method cannot be, only
  // another method checks it), the cheapest such.
  const double run_rtol = at(choice->pick).run_rtol;
  for (int i = 0; i < n; ++i) {
    const Candidate& c = at(i);
    if (!c.usable || c.check_cpu_s < 0.0) continue;
    if (i == choice->pick && !(c.check_rtol < run_rtol)) continue;
    if (choice->check < 0 || c.check_cpu_s < at(choice->check).check_cpu_s) choice->check = i;
  }
}

// What the choice says of its pick, in one sentence.
void ExplainPick(MethodChoice* choice) {
  if (choice->pick < 0) {
    choice->resolvable = false;
    choice->reason =
        "no candidate's pilot finished (see candidates' verdicts): the run goes with bdf at "
        "rtol " +
        FormatString("%.3g", choice->run.rtol);
    return;
  }
  const Candidate& pick = choice->candidates[static_cast<size_t>(choice->pick)];
  choice->run = WithCandidate(choice->run, pick, pick.run_rtol);
  choice->resolvable = pick.resolvable;
  choice->reason = FormatString(
      "%s at rtol %.3g: %s (predicted %.3g s of CPU); a mechanism with closed loops is "
      "piloted through its constraints over the whole run at three tolerances, its error "
      "fitted as a power of the tolerance (no stiffness probe of the constrained motion), "
      "and the verification measures the run",
      pick.name.c_str(), pick.run_rtol,
      pick.resolvable ? "the cheapest candidate predicted to meet the target"
                      : "no candidate is predicted to meet the target above the loops' "
                        "smallest tolerance 1e-10; the tightest",
      pick.run_cpu_s);
}

}  // namespace

RunResult RunLoopsWithTarget(const Model& model, const std::vector<LoopClosure>& loops,
                             const RunConfig& config, FrameSink* sink,
                             const std::atomic<bool>* cancel) {
  MBSTREAM_CHECK_MSG(config.target.any(), "a run without a target runs with SimulateLoops");
  const double cpu0 = ThreadCpuSeconds();
  MethodChoice choice;
  choice.run = WithCandidate(config, MakeCandidate(Method::kBdf), kLoopMinRtol);
  const FormulationChoice formulation = ValidateLoopRun(model, loops, choice.run);
  choice.formulation = FormulationName(formulation.formulation);
  choice.formulation_reason = formulation.reason;
  if (formulation.formulation == Formulation::kKinematic) {
    choice.closed_form = true;
    choice.run.formulation = Formulation::kKinematic;
    choice.reason =
        "every degree of freedom is prescribed: the loops are solved by Newton at each frame "
        "to round-off, nothing is integrated, so no method or tolerance is needed";
  } else {
    choice.run.formulation = Formulation::kJoint;
    ChooseAmongCandidates(LoopScene{model, loops, config, cancel}, &choice);
    ExplainPick(&choice);
  }
  choice.cpu_s = ThreadCpuSeconds() - cpu0;
  TrackingSink tracking(sink);
  RunResult result = SimulateLoops(model, loops, choice.run, &tracking, cancel);
  const Verification verification =
      VerifyTarget(model, config, choice, result, tracking.track(), cancel, loops);
  FinishTargetRun(config, choice, verification, &result);
  return result;
}

}  // namespace mbstream

#include "server/choose/pilot.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "server/choose/frame_track.h"
#include "server/sim/simulate.h"
#include "shared/common/format.h"

namespace mbstream {

namespace {

constexpr double kPilotFraction = 0.05;
constexpr double kTinyError = 1e-15;  // below this the pilots agree to round-off

// Growth of an error from the pilot span to the whole run: linear in time, as local errors
// accumulate into the global one, or exponential at `rate` (1/s) where nearby solutions
// separate (the Jacobian's largest real part, stiffness_probe.h), whichever is larger. (A
// pilot of 5 % of the run cannot tell how the error grows later: a servo's error may stay flat
// there and grow once the motion speeds up, and chaos shows only over seconds; fits of the
// growth within the pilot over- or underestimated it by orders of magnitude.)
double Growth(double span, double duration, double rate) {
  const double linear = std::max(1.0, duration / span);
  return std::max(linear, std::exp(std::min(std::max(rate, 0.0) * (duration - span), 700.0)));
}

}  // namespace

double PilotRtol(const AccuracyTarget& target, double min_rtol) {
  double smallest = std::numeric_limits<double>::infinity();
  for (double asked : {target.tcp_error_m, target.joint_error_rad, target.energy_error_rel}) {
    if (asked > 0.0) smallest = std::min(smallest, asked);
  }
  return std::clamp(smallest, 100.0 * min_rtol, kMaxRtol);
}

PilotSpan PilotSpanFor(const RunConfig& config) {
  PilotSpan pilot;
  const double interval = config.output_interval;
  const double span = std::max(kPilotFraction * config.duration, 2.0 * interval);
  // A whole number of the run's output intervals: the pilot's frames are then the run's first
  // frames, and the run can take a pilot over (run_prefix.h).
  pilot.span_s = std::min(config.duration, std::ceil(span / interval * (1.0 - 1e-12)) * interval);
  pilot.interval_s = std::min(config.output_interval, pilot.span_s / 4.0);
  return pilot;
}

RunResult RunPilot(const Model& model, const RunConfig& config, const PilotSpan& span, double rtol,
                   Candidate* candidate, const std::atomic<bool>* cancel) {
  candidate->piloted = true;
  candidate->pilots[0] = candidate->pilots[1] = nullptr;
  RunConfig pilot = config;
  pilot.formulation = Formulation::kJoint;
  pilot.duration = span.span_s;
  pilot.output_interval = span.interval_s;
  pilot.want_torques = false;
  pilot.max_steps = 0;  // the default budget of the span
  pilot.max_cpu_s = config.max_cpu_s > 0.0 ? 0.1 * config.max_cpu_s : 0.0;
  RunResult results[2];
  for (int k = 0; k < 2; ++k) {
    candidate->rtol[k] = std::max(kMinRtol, rtol / (k == 0 ? 1.0 : 100.0));
    // The pilot's integration is kept for the run or check that continues it.
    const PilotLink link{PilotToContinue(*candidate, candidate->rtol[k]),
                         /*keep_integration=*/true};
    results[k] = SimulateTree(model, WithCandidate(pilot, *candidate, candidate->rtol[k]), nullptr,
                              cancel, link);
    candidate->steps[k] = results[k].stats.solver.steps;
    candidate->rhs_evals[k] = results[k].stats.solver.rhs_evals;
    candidate->cpu_s[k] = results[k].stats.cpu_s;
    if (results[k].stats.status != RunStatus::kFinished) {
      candidate->verdict =
          FormatString("its pilot at rtol %.3g ended %s at t = %.4g s", candidate->rtol[k],
                       RunStatusName(results[k].stats.status), results[k].stats.t_reached);
      return results[1];
    }
  }
  const TrackDifference d = CompareTracks(TrackOf(results[0]), TrackOf(results[1]));
  candidate->error.tcp_m = d.tcp_m;
  candidate->error.joint_rad = d.joint_rad;
  candidate->error.energy_rel = results[0].stats.energy_error_max;
  const double step_ratio =
      static_cast<double>(std::max(candidate->steps[1], 1L)) / std::max(candidate->steps[0], 1L);
  candidate->steps_exponent =
      std::clamp(std::log(step_ratio) / std::log(candidate->rtol[0] / candidate->rtol[1]),
                 candidate->min_steps_exponent, 1.0);
  candidate->usable = true;
  for (int k = 0; k < 2; ++k) {
    candidate->pilots[k] =
        MakePrefix(results[k], candidate->rtol[k], MethodName(candidate->method));
  }
  return results[1];
}

namespace {

// The tolerance at which the candidate's predicted error over the whole run is `fraction`
// of the target; false when it lies below kMinRtol (then rtol = kMinRtol).
bool RtolFor(const AccuracyTarget& target, const Candidate& c, double fraction, double* rtol) {
  double best = kMaxRtol;
  auto limit = [&](double asked, double error, double growth) {
    if (!(asked > 0.0)) return;
    const double predicted = std::max(error, kTinyError) * growth;  // at rtol[0]
    best = std::min(best, c.rtol[0] * fraction * asked / predicted);
  };
  limit(target.tcp_error_m, c.error.tcp_m, c.growth.tcp_m);
  limit(target.joint_error_rad, c.error.joint_rad, c.growth.joint_rad);
  limit(target.energy_error_rel, c.error.energy_rel, c.growth.energy_rel);
  *rtol = std::max(best, kMinRtol);
  return best >= kMinRtol;
}

// From the tighter pilot: its steps are the least dominated by the start-up, and its
// tolerance is the nearer to the run's.
double PredictedCpu(const Candidate& c, double rtol, double duration, double span) {
  const double steps = static_cast<double>(std::max(c.steps[1], 1L)) *
                       std::pow(c.rtol[1] / rtol, c.steps_exponent) * duration / span;
  return std::max(steps * c.cpu_per_step_s, c.explicit_cpu_floor_s);
}

}  // namespace

void PredictCandidate(const AccuracyTarget& target, double duration, const PilotSpan& span,
                      double separation_rate, double rhs_cost_s, Candidate* candidate) {
  candidate->cpu_per_step_s = rhs_cost_s * static_cast<double>(candidate->rhs_evals[1]) /
                              static_cast<double>(std::max(candidate->steps[1], 1L));
  candidate->growth.tcp_m = Growth(span.span_s, duration, separation_rate);
  candidate->growth.joint_rad = Growth(span.span_s, duration, separation_rate);
  candidate->growth.energy_rel = Growth(span.span_s, duration, 0.0);  // chaos spares energy
  candidate->resolvable = RtolFor(target, *candidate, kRunSafety, &candidate->run_rtol);
  RtolFor(target, *candidate, kCheckSafety, &candidate->check_rtol);
  // At least as far below the run's as the safeties are apart (a run held at kMaxRtol would
  // otherwise be checked at its own tolerance).
  candidate->check_rtol = std::max(
      kMinRtol, std::min(candidate->check_rtol, candidate->run_rtol * kCheckSafety / kRunSafety));
  candidate->run_cpu_s = PredictedCpu(*candidate, candidate->run_rtol, duration, span.span_s);
  candidate->check_cpu_s = PredictedCpu(*candidate, candidate->check_rtol, duration, span.span_s);
}

}  // namespace mbstream

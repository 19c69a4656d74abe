#include "server/choose/method_choice.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "common/check.h"
#include "common/format.h"
#include "server/drives/drive_set.h"
#include "server/integrate/thread_cpu_clock.h"
#include "server/sim/initial_state.h"
#include "server/sim/run_validation.h"

namespace mbstream {

namespace {

// The pilots' looser tolerance: the tightest target, within what pilots resolve (the tighter
// pilot is 100 times below it).
double PilotRtol(const AccuracyTarget& target) {
  double smallest = std::numeric_limits<double>::infinity();
  for (double asked : {target.tcp_error_m, target.joint_error_rad, target.energy_error_rel}) {
    if (asked > 0.0) smallest = std::min(smallest, asked);
  }
  return std::clamp(smallest, 100.0 * kMinRtol, kMaxRtol);
}

// y = [q; qd] of frame k of a result.
Eigen::VectorXd StateOf(const RunResult& result, int k) {
  const int n = result.num_dofs;
  Eigen::VectorXd y(2 * n);
  for (int i = 0; i < n; ++i) {
    y(i) = result.q[static_cast<size_t>(k * n + i)];
    y(n + i) = result.qd[static_cast<size_t>(k * n + i)];
  }
  return y;
}

// The candidates, in the order they are considered: BDF first (stable whatever the stiffness;
// its pilot's states serve the stiffness probe), then the explicit methods, then DIRK.
std::vector<Candidate> CandidatesFor(const RunConfig& config) {
  if (!config.method_auto) return {MakeCandidate(config.method, config.erk_table)};
  return {MakeCandidate(Method::kBdf), MakeCandidate(Method::kErk),
          MakeCandidate(Method::kErk, "verner"), MakeCandidate(Method::kAdams),
          MakeCandidate(Method::kDirk)};
}

// A joint no servo holds and no trajectory prescribes (passive or under a torque law).
bool AnyFreeJoint(const RunConfig& config, int num_dofs) {
  if (static_cast<int>(config.drives.size()) < num_dofs) return true;
  return std::any_of(config.drives.begin(), config.drives.end(), [](const DriveConfig& d) {
    return d.kind != DriveConfig::Kind::kPdServo && d.kind != DriveConfig::Kind::kPrescribed;
  });
}

bool IsExplicit(const Candidate& c) { return c.stability_reach > 0.0; }

constexpr double kSeparationShare = 0.75;
// A looser pilot the run may go on from on a scene held by servos: its measured error at
// most this share of the target.
constexpr double kLooserPilotShare = 0.1;

// Whether every error asked for and measured is within `share` of its target.
bool WithinShare(const AccuracyTarget& target, const ErrorFigures& error, double share) {
  bool any = false;
  for (auto [asked, value] : {std::pair{target.tcp_error_m, error.tcp_m},
                              std::pair{target.joint_error_rad, error.joint_rad},
                              std::pair{target.energy_error_rel, error.energy_rel}}) {
    if (!(asked > 0.0)) continue;
    if (!(value >= 0.0 && value <= share * asked)) return false;
    any = true;
  }
  return any;
}
constexpr double kRepilotBelow = 10.0;  // re-pilot when the run's rtol is this far below

std::string Pretty(double value) { return FormatString("%.3g", value); }

}  // namespace

MethodChoice ChooseMethod(const Model& model_in, const RunConfig& config,
                          const std::atomic<bool>* cancel) {
  const double cpu0 = ThreadCpuSeconds();
  MethodChoice choice;
  Model model = model_in;
  model.gravity = config.gravity;
  const DriveSet drives(model, config.drives);
  const FormulationChoice formulation = ValidateRun(model, config, drives);
  choice.formulation = FormulationName(formulation.formulation);
  choice.formulation_reason = formulation.reason;
  choice.run = config;
  choice.run.target = AccuracyTarget{};
  choice.run.method_auto = false;
  if (formulation.formulation == Formulation::kKinematic) {
    choice.closed_form = true;
    choice.run.formulation = Formulation::kKinematic;
    choice.reason =
        "every joint is prescribed: the closed form is exact (error 0) and integrates nothing, "
        "so no method or tolerance is needed";
    choice.cpu_s = ThreadCpuSeconds() - cpu0;
    return choice;
  }
  choice.run.formulation = Formulation::kJoint;
  choice.pilot = PilotSpanFor(config);
  choice.candidates = CandidatesFor(config);
  const double duration = config.duration;
  double rtol = PilotRtol(config.target);

  // The first candidate's pilot, then the stiffness at the initial state and, unless that
  // alone settles what the samples decide, at three of its states.
  Candidate& first = choice.candidates.front();
  const RunResult tight = RunPilot(model, config, choice.pilot, rtol, &first, cancel);
  std::vector<double> times{0.0};
  std::vector<Eigen::VectorXd> states{InitialJointState(config, drives, model.num_dofs())};
  choice.stiffness = ProbeStiffness(model, drives, times, states);
  for (int k : {tight.num_frames() / 3, 2 * tight.num_frames() / 3, tight.num_frames() - 1}) {
    if (k > 0 && k < tight.num_frames()) {
      times.push_back(tight.t[static_cast<size_t>(k)]);
      states.push_back(StateOf(tight, k));
    }
  }
  // Errors grow exponentially only where some joint is free: a servo on every joint
  // contracts nearby trajectories whatever the local real parts (seed-servo has 1.9 1/s and
  // its error does not grow), damping on one joint does not stop the others separating.
  // There, 0.75 of the local rate: the average separation (the Lyapunov exponent) is smaller
  // than its largest local value.
  const bool free_joint = AnyFreeJoint(config, model.num_dofs());
  auto predict = [&](Candidate* c) {
    const double separation =
        free_joint ? kSeparationShare * choice.stiffness.separation_rate : 0.0;
    choice.separation_rate_used = separation;
    PredictCandidate(config.target, duration, choice.pilot, separation, choice.stiffness.rhs_cost_s,
                     c);
  };
  if (first.usable) predict(&first);
  // Where the run's tolerance lies far below the pilots' (a chaotic scene: errors grow a
  // million times), the error per tolerance would be extrapolated over decades, and it is not
  // proportional over decades (BDF's and Adams' exponent is below 1): pilot again at ten
  // times the predicted tolerance, the other candidates there too.
  if (first.usable && first.run_rtol < first.rtol[1] / kRepilotBelow) {
    rtol = std::max(10.0 * first.run_rtol, 100.0 * kMinRtol);
    first = MakeCandidate(first.method, first.table);
    RunPilot(model, config, choice.pilot, rtol, &first, cancel);
    if (first.usable) predict(&first);
  }
  // The explicit candidates' CPU floor (stability alone) at the stiffness seen so far.
  auto explicit_floor = [&](Candidate* c) {
    const double h = ExplicitStepLimit(c->stability_reach, choice.stiffness.largest);
    c->explicit_cpu_floor_s = duration / h * c->rhs_per_step * choice.stiffness.rhs_cost_s;
    return h;
  };
  // More samples can only raise the largest eigenvalue (and matter to the growth only when
  // nothing dissipates): they are needed unless every explicit candidate is already out.
  bool settled = first.usable && !free_joint && choice.stiffness.largest > 0.0;
  for (Candidate& c : choice.candidates) {
    if (!IsExplicit(c) || !settled) continue;
    explicit_floor(&c);
    settled = c.explicit_cpu_floor_s > 3.0 * first.run_cpu_s;
  }
  if (!settled && states.size() > 1) {
    choice.stiffness = ProbeStiffness(model, drives, times, states);
    if (first.usable) predict(&first);
  }
  if (first.method == Method::kBdf && first.steps[0] > 0) {
    choice.bdf_mean_step_s = choice.pilot.span_s / static_cast<double>(first.steps[0]);
  }

  for (size_t k = 1; k < choice.candidates.size(); ++k) {
    Candidate& c = choice.candidates[k];
    if (c.method == Method::kDirk && config.method_auto) {
      c.verdict =
          "not piloted: like bdf it is stable on stiff scenes, but it solves 4 implicit stages a "
          "step where bdf solves one (docs/accuracy.md: 5-100 times bdf's CPU on the reference "
          "scenes)";
      continue;
    }
    if (IsExplicit(c) && choice.stiffness.largest > 0.0) {
      const double h = explicit_floor(&c);
      if (first.usable && c.explicit_cpu_floor_s > 3.0 * first.run_cpu_s) {
        c.verdict = "not piloted: stability alone holds its step below " + Pretty(h) +
                    " s (|lambda| " + Pretty(choice.stiffness.largest) + " 1/s), which costs at " +
                    "least " + Pretty(c.explicit_cpu_floor_s) + " s of CPU, more than 3 x " +
                    first.name + "'s predicted " + Pretty(first.run_cpu_s) + " s";
        continue;
      }
    }
    RunPilot(model, config, choice.pilot, rtol, &c, cancel);
    if (c.usable) predict(&c);
  }

  for (size_t k = 0; k < choice.candidates.size(); ++k) {
    const Candidate& c = choice.candidates[k];
    if (!c.usable) continue;
    // The cheapest candidate predicted to reach the target; one that is not only if none is.
    const Candidate* best = choice.pick < 0 ? nullptr : &choice.candidates[choice.pick];
    if (best == nullptr || (c.resolvable && !best->resolvable) ||
        (c.resolvable == best->resolvable && c.run_cpu_s < best->run_cpu_s)) {
      choice.pick = static_cast<int>(k);
    }
    if (choice.check < 0 || c.check_cpu_s < choice.candidates[choice.check].check_cpu_s) {
      choice.check = static_cast<int>(k);
    }
  }
  // The check must differ from the run: at the floor tolerance the same method would repeat
  // it. Then the cheapest other candidate, if any.
  if (choice.pick >= 0 && choice.check == choice.pick &&
      choice.candidates[choice.pick].check_rtol > 0.5 * choice.candidates[choice.pick].run_rtol) {
    choice.check = -1;
    for (size_t k = 0; k < choice.candidates.size(); ++k) {
      const Candidate& c = choice.candidates[k];
      if (!c.usable || static_cast<int>(k) == choice.pick) continue;
      if (choice.check < 0 || c.check_cpu_s < choice.candidates[choice.check].check_cpu_s) {
        choice.check = static_cast<int>(k);
      }
    }
  }
  choice.cpu_s = ThreadCpuSeconds() - cpu0;
  if (choice.pick < 0) {
    choice.run.method = config.method_auto ? Method::kBdf : config.method;
    choice.reason = "no candidate's pilot finished; running " +
                    std::string(MethodName(choice.run.method)) + " at rtol " +
                    Pretty(choice.run.rtol) + " as given";
    return choice;
  }
  const Candidate& pick = choice.candidates[static_cast<size_t>(choice.pick)];
  choice.resolvable = pick.resolvable;
  choice.run = WithCandidate(config, pick, pick.run_rtol);
  choice.run.formulation = Formulation::kJoint;
  // The run goes on from a pilot at least as tight as itself (WithCandidate) or, on a scene
  // held by servos, where an error of the state at the pilot's end does not grow, from a
  // looser one whose error is within a tenth of the target (the looser pilot's as measured,
  // the tighter's in proportion to its tolerance): the loosest such, which leaves the
  // tighter pilot to the check where it can. (The check compares the whole run, the pilot's
  // frames included, with its own.)
  for (int k = 0; k < 2 && !free_joint; ++k) {
    const std::shared_ptr<const RunPrefix>& pilot = pick.pilots[k];
    if (pilot == nullptr) continue;
    if (choice.run.prefix != nullptr && choice.run.prefix->rtol >= pilot->rtol) break;
    if (!pilot->HasIntegration()) continue;
    const double share = kLooserPilotShare * pick.rtol[0] / pilot->rtol;
    if (WithinShare(config.target, pick.error, share)) {
      choice.run.prefix = pilot;
      break;
    }
  }
  choice.reason = pick.name + " at rtol " + Pretty(pick.run_rtol) +
                  " has the lowest predicted CPU time (" + Pretty(pick.run_cpu_s) +
                  " s) for an error predicted at " + Pretty(kRunSafety) + " x the target";
  if (!pick.resolvable) {
    choice.reason += "; but the target is not resolvable: even rtol " + Pretty(kMinRtol) +
                     " is predicted to miss it (the error grows " +
                     Pretty(std::max(pick.growth.tcp_m, pick.growth.joint_rad)) +
                     " times from the pilot to the end of the run)";
  }
  return choice;
}

}  // namespace mbstream

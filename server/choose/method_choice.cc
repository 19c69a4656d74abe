#include "server/choose/method_choice.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "server/drives/drive_set.h"
#include "server/integrate/thread_cpu_clock.h"
#include "server/sim/initial_state.h"
#include "server/sim/run_validation.h"
#include "shared/common/check.h"
#include "shared/common/format.h"

namespace mbstream {

namespace {

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

// What the steps of a choice share: the scene (the model with the run's gravity) and whether
// any joint is free.
struct ChoiceScene {
  const Model& model;
  const DriveSet& drives;
  const RunConfig& config;
  const std::atomic<bool>* cancel;
  // Errors grow exponentially only where some joint is free: a servo on every joint
  // contracts nearby trajectories whatever the local real parts (seed-servo has 1.9 1/s and
  // its error does not grow), damping on one joint does not stop the others separating.
  bool free_joint = false;
};

// The states the stiffness is probed at: the initial state, then some of a pilot's.
struct StiffnessSamples {
  std::vector<double> times;
  std::vector<Eigen::VectorXd> states;
};

// The formulation and the run's configuration before any pilot (its target dropped); true
// when the closed form settles the choice.
bool StartChoice(const Model& model, const RunConfig& config, const DriveSet& drives,
                 MethodChoice* choice) {
  const FormulationChoice formulation = ValidatedFormulation(model, config, drives);
  choice->formulation = FormulationName(formulation.formulation);
  choice->formulation_reason = formulation.reason;
  choice->run = config;
  choice->run.target = AccuracyTarget{};
  choice->run.method_auto = false;
  if (formulation.formulation == Formulation::kKinematic) {
    choice->closed_form = true;
    choice->run.formulation = Formulation::kKinematic;
    choice->reason =
        "every joint is prescribed: the closed form is exact (error 0) and integrates nothing, "
        "so no method or tolerance is needed";
    return true;
  }
  choice->run.formulation = Formulation::kJoint;
  return false;
}

// The candidate's predictions at the stiffness seen so far. Where some joint is free, 0.75
// of the local rate: the average separation (the Lyapunov exponent) is smaller than its
// largest local value.
void Predict(const ChoiceScene& scene, MethodChoice* choice, Candidate* c) {
  const double separation =
      scene.free_joint ? kSeparationShare * choice->stiffness.separation_rate : 0.0;
  choice->separation_rate_used = separation;
  PredictCandidate(scene.config.target, scene.config.duration, choice->pilot, separation,
                   choice->stiffness.rhs_cost_s, c);
}

// An explicit candidate's CPU floor (stability alone) at the stiffness seen so far; returns
// the step stability allows.
double ExplicitFloor(const MethodChoice& choice, double duration, Candidate* c) {
  const double h = ExplicitStepLimit(c->stability_reach, choice.stiffness.largest);
  c->explicit_cpu_floor_s = duration / h * c->rhs_per_step * choice.stiffness.rhs_cost_s;
  return h;
}

// The first candidate's pilot, then the stiffness at the initial state; returns the pilots'
// tolerance and fills `samples` with three of the pilot's states for a closer look.
double PilotFirstCandidate(const ChoiceScene& scene, MethodChoice* choice,
                           StiffnessSamples* samples) {
  const RunConfig& config = scene.config;
  double rtol = PilotRtol(config.target);
  Candidate& first = choice->candidates.front();
  const RunResult tight = RunPilot(scene.model, config, choice->pilot, rtol, &first, scene.cancel);
  samples->times = {0.0};
  samples->states = {InitialJointState(config, scene.drives, scene.model.num_dofs())};
  choice->stiffness = ProbeStiffness(scene.model, scene.drives, samples->times, samples->states);
  for (int k : {tight.num_frames() / 3, 2 * tight.num_frames() / 3, tight.num_frames() - 1}) {
    if (k > 0 && k < tight.num_frames()) {
      samples->times.push_back(tight.t[static_cast<size_t>(k)]);
      samples->states.push_back(StateOf(tight, k));
    }
  }
  if (first.usable) Predict(scene, choice, &first);
  // Where the run's tolerance lies far below the pilots' (a chaotic scene: errors grow a
  // million times), the error per tolerance would be extrapolated over decades, and it is not
  // proportional over decades (BDF's and Adams' exponent is below 1): pilot again at ten
  // times the predicted tolerance, the other candidates there too.
  if (first.usable && first.run_rtol < first.rtol[1] / kRepilotBelow) {
    rtol = std::max(10.0 * first.run_rtol, 100.0 * kMinRtol);
    first = MakeCandidate(first.method, first.table);
    RunPilot(scene.model, config, choice->pilot, rtol, &first, scene.cancel);
    if (first.usable) Predict(scene, choice, &first);
  }
  return rtol;
}

// The stiffness at the pilot's sampled states too, unless the initial state alone settles
// what they would decide. More samples can only raise the largest eigenvalue (and matter to
// the growth only when nothing dissipates): they are needed unless every explicit candidate
// is already out.
void ProbeSampledStiffness(const ChoiceScene& scene, const StiffnessSamples& samples,
                           MethodChoice* choice) {
  Candidate& first = choice->candidates.front();
  bool settled = first.usable && !scene.free_joint && choice->stiffness.largest > 0.0;
  for (Candidate& c : choice->candidates) {
    if (!IsExplicit(c) || !settled) continue;
    ExplicitFloor(*choice, scene.config.duration, &c);
    settled = c.explicit_cpu_floor_s > 3.0 * first.run_cpu_s;
  }
  if (!settled && samples.states.size() > 1) {
    choice->stiffness = ProbeStiffness(scene.model, scene.drives, samples.times, samples.states);
    if (first.usable) Predict(scene, choice, &first);
  }
}

// The other candidates' pilots at `rtol`, but for those excluded up front: DIRK (when the
// method is chosen) and explicit methods whose stability alone costs more than 3 x the first
// candidate's predicted CPU.
void PilotOtherCandidates(const ChoiceScene& scene, double rtol, MethodChoice* choice) {
  const Candidate& first = choice->candidates.front();
  for (size_t k = 1; k < choice->candidates.size(); ++k) {
    Candidate& c = choice->candidates[k];
    if (c.method == Method::kDirk && scene.config.method_auto) {
      c.verdict =
          "not piloted: like bdf it is stable on stiff scenes, but it solves 4 implicit stages a "
          "step where bdf solves one (docs/accuracy.md: 5-100 times bdf's CPU on the reference "
          "scenes)";
      continue;
    }
    if (IsExplicit(c) && choice->stiffness.largest > 0.0) {
      const double h = ExplicitFloor(*choice, scene.config.duration, &c);
      if (first.usable && c.explicit_cpu_floor_s > 3.0 * first.run_cpu_s) {
        c.verdict = "not piloted: stability alone holds its step below " + Pretty(h) +
                    " s (|lambda| " + Pretty(choice->stiffness.largest) + " 1/s), which costs " +
                    "at least " + Pretty(c.explicit_cpu_floor_s) + " s of CPU, more than 3 x " +
                    first.name + "'s predicted " + Pretty(first.run_cpu_s) + " s";
        continue;
      }
    }
    RunPilot(scene.model, scene.config, choice->pilot, rtol, &c, scene.cancel);
    if (c.usable) Predict(scene, choice, &c);
  }
}

// The pick (the cheapest candidate predicted to reach the target; one that is not only if
// none is) and the check (the cheapest to check with, another than the pick when the pick's
// check tolerance would repeat its run).
void PickAndCheck(MethodChoice* choice) {
  std::vector<Candidate>& candidates = choice->candidates;
  for (size_t k = 0; k < candidates.size(); ++k) {
    const Candidate& c = candidates[k];
    if (!c.usable) continue;
    const Candidate* best = choice->pick < 0 ? nullptr : &candidates[choice->pick];
    if (best == nullptr || (c.resolvable && !best->resolvable) ||
        (c.resolvable == best->resolvable && c.run_cpu_s < best->run_cpu_s)) {
      choice->pick = static_cast<int>(k);
    }
    if (choice->check < 0 || c.check_cpu_s < candidates[choice->check].check_cpu_s) {
      choice->check = static_cast<int>(k);
    }
  }
  // The check must differ from the run: at the floor tolerance the same method would repeat
  // it. Then the cheapest other candidate, if any.
  if (choice->pick >= 0 && choice->check == choice->pick &&
      candidates[choice->pick].check_rtol > 0.5 * candidates[choice->pick].run_rtol) {
    choice->check = -1;
    for (size_t k = 0; k < candidates.size(); ++k) {
      const Candidate& c = candidates[k];
      if (!c.usable || static_cast<int>(k) == choice->pick) continue;
      if (choice->check < 0 || c.check_cpu_s < candidates[choice->check].check_cpu_s) {
        choice->check = static_cast<int>(k);
      }
    }
  }
}

// The run of the pick: its method and tolerance, the pilot it goes on from, and the reason.
void SettlePick(const ChoiceScene& scene, MethodChoice* choice) {
  const RunConfig& config = scene.config;
  const Candidate& pick = choice->candidates[static_cast<size_t>(choice->pick)];
  choice->resolvable = pick.resolvable;
  choice->run = WithCandidate(config, pick, pick.run_rtol);
  choice->run.formulation = Formulation::kJoint;
  choice->continues = PilotToContinue(pick, pick.run_rtol);
  // The run goes on from a pilot at least as tight as itself (PilotToContinue) or, on a scene
  // held by servos, where an error of the state at the pilot's end does not grow, from a
  // looser one whose error is within a tenth of the target (the looser pilot's as measured,
  // the tighter's in proportion to its tolerance): the loosest such, which leaves the
  // tighter pilot to the check where it can. (The check compares the whole run, the pilot's
  // frames included, with its own.)
  for (int k = 0; k < 2 && !scene.free_joint; ++k) {
    const std::shared_ptr<const RunPrefix>& pilot = pick.pilots[k];
    if (pilot == nullptr) continue;
    if (choice->continues != nullptr && choice->continues->rtol >= pilot->rtol) break;
    if (!pilot->HasIntegration()) continue;
    const double share = kLooserPilotShare * pick.rtol[0] / pilot->rtol;
    if (WithinShare(config.target, pick.error, share)) {
      choice->continues = pilot;
      break;
    }
  }
  choice->reason = pick.name + " at rtol " + Pretty(pick.run_rtol) +
                   " has the lowest predicted CPU time (" + Pretty(pick.run_cpu_s) +
                   " s) for an error predicted at " + Pretty(kRunSafety) + " x the target";
  if (!pick.resolvable) {
    choice->reason += "; but the target is not resolvable: even rtol " + Pretty(kMinRtol) +
                      " is predicted to miss it (the error grows " +
                      Pretty(std::max(pick.growth.tcp_m, pick.growth.joint_rad)) +
                      " times from the pilot to the end of the run)";
  }
}

}  // namespace

MethodChoice ChooseMethod(const Model& model_in, const RunConfig& config,
                          const std::atomic<bool>* cancel) {
  const double cpu0 = ThreadCpuSeconds();
  MethodChoice choice;
  Model model = model_in;
  model.gravity = config.gravity;
  const DriveSet drives(model, config.drives);
  if (StartChoice(model, config, drives, &choice)) {
    choice.cpu_s = ThreadCpuSeconds() - cpu0;
    return choice;
  }
  const ChoiceScene scene{model, drives, config, cancel, AnyFreeJoint(config, model.num_dofs())};
  choice.pilot = PilotSpanFor(config);
  choice.candidates = CandidatesFor(config);
  StiffnessSamples samples;
  const double rtol = PilotFirstCandidate(scene, &choice, &samples);
  ProbeSampledStiffness(scene, samples, &choice);
  const Candidate& first = choice.candidates.front();
  if (first.method == Method::kBdf && first.steps[0] > 0) {
    choice.bdf_mean_step_s = choice.pilot.span_s / static_cast<double>(first.steps[0]);
  }
  PilotOtherCandidates(scene, rtol, &choice);
  PickAndCheck(&choice);
  choice.cpu_s = ThreadCpuSeconds() - cpu0;
  if (choice.pick < 0) {
    choice.run.method = config.method_auto ? Method::kBdf : config.method;
    choice.reason = "no candidate's pilot finished; running " +
                    std::string(MethodName(choice.run.method)) + " at rtol " +
                    Pretty(choice.run.rtol) + " as given";
    return choice;
  }
  SettlePick(scene, &choice);
  return choice;
}

}  // namespace mbstream

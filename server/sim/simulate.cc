#include "server/sim/simulate.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <string>

#include "server/drives/drive_set.h"
#include "server/integrate/failure_messages.h"
#include "server/integrate/thread_cpu_clock.h"
#include "server/model/coordinate_names.h"
#include "server/sim/body_run.h"
#include "server/sim/frame_recorder.h"
#include "server/sim/input_sanity.h"
#include "server/sim/joint_run.h"
#include "server/sim/kinematic_run.h"
#include "server/sim/run_budget.h"
#include "server/sim/run_trust.h"
#include "server/sim/run_validation.h"
#include "shared/common/check.h"
#include "shared/common/format.h"

namespace mbstream {

namespace {

// Frames at 0, interval, 2 interval, ... up to `duration`.
long RegularFrameCount(double duration, double interval) {
  return static_cast<long>(std::floor(duration / interval * (1.0 + 1e-12))) + 1;
}

// Output times k * interval up to the duration, the duration itself always last.
// Frame k at k * interval, and a last one at `duration` when it is not a multiple.
std::vector<double> OutputTimes(double duration, double interval) {
  const long regular = RegularFrameCount(duration, interval);
  std::vector<double> times;
  times.reserve(static_cast<size_t>(OutputFrameCount(duration, interval)));
  for (long k = 0; k < regular; ++k) times.push_back(std::min(duration, k * interval));
  if (duration - times.back() > 1e-12 * duration) times.push_back(duration);
  return times;
}

// What ran out and why, for the message of a run whose budget did.
BudgetReport BudgetReportOf(const RunConfig& config, const RunStats& stats,
                            const BudgetTracking& budget,
                            const std::vector<InputWarning>& warnings) {
  BudgetReport report;
  report.steps = stats.solver.steps;
  report.cpu = stats.solver.steps < config.max_steps;
  report.cpu_s = stats.cpu_s;
  report.t_reached = budget.t_stop;
  report.duration = config.duration;
  report.last_step = stats.solver.last_step;
  report.advice = budget.advice;
  for (const InputWarning& warning : warnings) {
    if (warning.rate > 0.0) report.causes.push_back(warning.message);
  }
  if (budget.eigenvalue > 0.0) {
    std::string stiff = FormatString(
        "the scene is stiff there: the largest eigenvalue of the ODE's Jacobian at t = %.6g s "
        "is about %.3g 1/s",
        budget.t_stop, budget.eigenvalue);
    const bool explicit_method = config.method == Method::kAdams || config.method == Method::kErk ||
                                 config.method == Method::kRk4 || config.method == Method::kEuler;
    if (explicit_method) {
      stiff += FormatString(", so method %s needs steps below about %.3g s: use method bdf or dirk",
                            MethodName(config.method), 3.0 / budget.eigenvalue);
    }
    report.causes.push_back(stiff);
  }
  return report;
}

}  // namespace

long OutputFrameCount(double duration, double interval) {
  const long regular = RegularFrameCount(duration, interval);
  const double last = std::min(duration, (regular - 1) * interval);
  return regular + (duration - last > 1e-12 * duration ? 1 : 0);
}

RunResult SimulateTree(const Model& model_in, const RunConfig& config_in, FrameSink* sink,
                       const std::atomic<bool>* cancel, const PilotLink& pilot,
                       ControlLaw* control) {
  const double cpu0 = ThreadCpuSeconds();
  const auto wall0 = std::chrono::steady_clock::now();
  Model model = model_in;  // the run's own copy, with the run's gravity
  model.gravity = config_in.gravity;
  RunConfig config = config_in;
  ResolveBudget(model.num_dofs(), &config);
  const DriveSet drives(model, config.drives);
  const FormulationChoice choice = ValidatedFormulation(model, config, drives);
  const std::vector<InputWarning> warnings = CheckInputSanity(model, config);

  RunResult result;
  result.num_dofs = model.num_dofs();
  result.joint_names = VelocityNames(model);  // one per body without quaternions
  if (model.has_quaternions()) {
    result.num_positions = model.nq();
    result.position_names = PositionNames(model);
    result.position_index.assign(static_cast<size_t>(model.nv()), -1);
    for (const Body& body : model.bodies) {
      if (body.nv() == 1) result.position_index[static_cast<size_t>(body.v_index)] = body.q_index;
    }
  }
  const bool kinematic = choice.formulation == Formulation::kKinematic;
  result.has_torques = config.want_torques;
  result.has_energy = !kinematic;
  result.stats.formulation = FormulationName(choice.formulation);
  result.stats.formulation_reason = choice.reason;
  result.stats.method = kinematic ? "none" : MethodName(config.method);
  result.stats.integrator = kinematic ? "none (closed form)" : "";
  result.stats.warnings = WarningMessages(warnings);
  result.stats.max_steps = config.max_steps;
  result.stats.max_cpu_s = config.max_cpu_s;

  const std::vector<double> times = OutputTimes(config.duration, config.output_interval);
  FrameRecorder recorder(model, drives, result, times.size(), /*track_tcp_error=*/!kinematic,
                         /*latest_only=*/sink != nullptr && sink->KeepsFrames());
  BudgetTracking budget;
  budget.cpu_deadline_s = cpu0 + config.max_cpu_s;
  if (kinematic) {
    RunKinematic(model, config, drives, times, recorder, result, sink, cancel);
  } else if (IsBodyFormulation(choice.formulation)) {
    RunBody(model, config, choice.formulation, drives, times, recorder, result, sink, cancel,
            &budget);
  } else {
    RunJointSpace(model, config, pilot, drives, times, recorder, result, sink, cancel, &budget,
                  control);
  }
  result.stats.cpu_s = ThreadCpuSeconds() - cpu0;
  result.stats.wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  if (result.stats.status == RunStatus::kTooMuchWork) {
    result.stats.message =
        BudgetMessage(config, BudgetReportOf(config, result.stats, budget, warnings));
  }
  AssessTrust(&result.stats, TrustScaleOf(model, config, choice.formulation));
  return result;
}

}  // namespace mbstream

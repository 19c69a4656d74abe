#include "server/sim/simulate.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <memory>

#include "server/common/check.h"
#include "server/dynamics/rnea.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/sim/advance_to_frame.h"
#include "server/sim/body_run.h"
#include "server/sim/drive_set.h"
#include "server/sim/formulation_choice.h"
#include "server/sim/frame_recorder.h"
#include "server/sim/initial_state.h"
#include "server/sim/joint_space_ode.h"

namespace mbstream {

namespace {

// Frames at 0, interval, 2 interval, ... up to `duration`.
long RegularFrameCount(double duration, double interval) {
  return static_cast<long>(std::floor(duration / interval * (1.0 + 1e-12))) + 1;
}

double ThreadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
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

void RunKinematic(const Model& model, const RunConfig& config, const DriveSet& drives,
                  const std::vector<double>& times, FrameRecorder& recorder, RunResult& result,
                  FrameSink* sink, const std::atomic<bool>* cancel) {
  const int n = model.num_dofs();
  Data data(model);
  Eigen::VectorXd q(n), qd(n), qdd(n), effort(n);
  for (double t : times) {
    if (cancel && cancel->load(std::memory_order_relaxed)) {
      result.stats.status = RunStatus::kCancelled;
      result.stats.message = "cancelled at t = " + std::to_string(result.stats.t_reached) + " s";
      return;
    }
    for (int i = 0; i < n; ++i) {
      const TrajectoryPoint ref = drives.Reference(i, t);
      q(i) = ref.q;
      qd(i) = ref.qd;
      qdd(i) = ref.qdd;
    }
    if (config.want_torques) {
      effort = Rnea(model, data, q, qd, qdd);
      for (int i = 0; i < n; ++i) effort(i) += drives.damping(i) * qd(i);
    }
    if (!recorder.Record(t, q, qd, config.want_torques ? &effort : nullptr)) {
      result.stats.status = RunStatus::kDiverged;
      result.stats.message =
          "a prescribed trajectory gave a non-finite value at t = " + std::to_string(t) +
          " s; check the drives' parameters";
      return;
    }
    if (sink) sink->OnFrame(result, result.num_frames() - 1);
  }
}

void RunJointSpace(const Model& model, const RunConfig& config, const DriveSet& drives,
                   const std::vector<double>& times, FrameRecorder& recorder, RunResult& result,
                   FrameSink* sink, const std::atomic<bool>* cancel) {
  const int n = model.num_dofs();
  JointSpaceOde ode(model, drives);
  result.stats.equations = ode.size();
  result.stats.jacobian_nnz = ode.JacobianNonZeros();
  Eigen::VectorXd y = InitialJointState(config, drives, n);
  std::unique_ptr<Integrator> integrator =
      MakeIntegrator(ode, 0.0, y.data(), IntegratorOptionsFrom(config, times.back()));
  result.stats.integrator = integrator->name();
  const bool need_effort = result.has_torques || result.has_energy;
  for (size_t k = 0; k < times.size(); ++k) {
    if (!AdvanceToFrame(*integrator, times, k, y.data(), cancel, &result.stats)) break;
    const bool finite = ode.EvaluateOutputs(times[k], y.data(), need_effort);
    if (!finite || !recorder.Record(times[k], ode.q(), ode.qd(),
                                    need_effort ? &ode.drive_effort() : nullptr)) {
      result.stats.status = RunStatus::kDiverged;
      result.stats.message = "the state became non-finite at t = " + std::to_string(times[k]) +
                             " s; use a smaller step or an implicit method (bdf, dirk)";
      break;
    }
    if (sink) sink->OnFrame(result, result.num_frames() - 1);
  }
  result.stats.solver = integrator->stats();
}

}  // namespace

long OutputFrameCount(double duration, double interval) {
  const long regular = RegularFrameCount(duration, interval);
  const double last = std::min(duration, (regular - 1) * interval);
  return regular + (duration - last > 1e-12 * duration ? 1 : 0);
}

RunResult Simulate(const Model& model_in, const RunConfig& config, FrameSink* sink,
                   const std::atomic<bool>* cancel) {
  const double cpu0 = ThreadCpuSeconds();
  const auto wall0 = std::chrono::steady_clock::now();
  Model model = model_in;  // the run's own copy, with the run's gravity
  model.gravity = config.gravity;
  const DriveSet drives(model, config);
  const FormulationChoice choice = ChooseFormulation(config, drives);

  RunResult result;
  result.num_dofs = model.num_dofs();
  for (const Body& body : model.bodies) result.joint_names.push_back(body.joint.name);
  const bool kinematic = choice.formulation == Formulation::kKinematic;
  result.has_torques = config.want_torques;
  result.has_energy = !kinematic;
  result.stats.formulation = FormulationName(choice.formulation);
  result.stats.formulation_reason = choice.reason;
  result.stats.method = kinematic ? "none" : MethodName(config.method);
  result.stats.integrator = kinematic ? "none (closed form)" : "";

  const std::vector<double> times = OutputTimes(config.duration, config.output_interval);
  FrameRecorder recorder(model, drives, result, times.size(), /*track_tcp_error=*/!kinematic,
                         /*latest_only=*/sink != nullptr && sink->KeepsFrames());
  if (kinematic) {
    RunKinematic(model, config, drives, times, recorder, result, sink, cancel);
  } else if (IsBodyFormulation(choice.formulation)) {
    RunBody(model, config, choice.formulation, drives, times, recorder, result, sink, cancel);
  } else {
    RunJointSpace(model, config, drives, times, recorder, result, sink, cancel);
  }
  result.stats.cpu_s = ThreadCpuSeconds() - cpu0;
  result.stats.wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return result;
}

}  // namespace mbstream

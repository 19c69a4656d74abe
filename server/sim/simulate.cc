#include "server/sim/simulate.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <memory>

#include "server/common/check.h"
#include "server/dynamics/energy.h"
#include "server/dynamics/rnea.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/sim/drive_set.h"
#include "server/sim/formulation_choice.h"
#include "server/sim/joint_space_ode.h"

namespace mbstream {

namespace {

double ThreadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// Output times k * interval up to the duration, the duration itself always last.
std::vector<double> OutputTimes(double duration, double interval) {
  std::vector<double> times;
  const auto count = static_cast<long>(std::floor(duration / interval * (1.0 + 1e-12)));
  times.reserve(static_cast<size_t>(count) + 2);
  for (long k = 0; k <= count; ++k) times.push_back(std::min(duration, k * interval));
  if (duration - times.back() > 1e-12 * duration) times.push_back(duration);
  return times;
}

RunStatus ToRunStatus(IntegratorStatus status) {
  switch (status) {
    case IntegratorStatus::kOk:
      return RunStatus::kFinished;
    case IntegratorStatus::kDiverged:
      return RunStatus::kDiverged;
    case IntegratorStatus::kTooMuchWork:
      return RunStatus::kTooMuchWork;
    case IntegratorStatus::kErrorTestFailures:
      return RunStatus::kErrorTestFailures;
    case IntegratorStatus::kConvergenceFailures:
      return RunStatus::kConvergenceFailures;
    case IntegratorStatus::kRhsFailure:
    case IntegratorStatus::kSetupFailure:
      return RunStatus::kFailed;
  }
  return RunStatus::kFailed;
}

// Appends frames to a RunResult: TCP, energies, and the accuracy figures.
class FrameRecorder {
 public:
  // track_tcp_error: compare the TCP with direct kinematics of the prescribed motion (off
  // when the states are that motion, as in the kinematic formulation: the error is 0).
  FrameRecorder(const Model& model, const DriveSet& drives, RunResult& result, size_t frames,
                bool track_tcp_error)
      : model_(model),
        drives_(drives),
        result_(result),
        data_(model),
        q_ref_(model.num_dofs()),
        track_tcp_error_(track_tcp_error && drives.all_prescribed() && model.tcp_frame >= 0) {
    const size_t n = static_cast<size_t>(model.num_dofs());
    result_.t.reserve(frames);
    result_.q.reserve(frames * n);
    result_.qd.reserve(frames * n);
    result_.tcp.reserve(frames * 3);
    if (result_.has_torques) result_.tau.reserve(frames * n);
    if (result_.has_energy) {
      result_.kinetic.reserve(frames);
      result_.potential.reserve(frames);
    }
    if (drives_.all_prescribed()) result_.stats.tcp_error_max = 0.0;
    if (result_.has_energy) {
      result_.stats.energy_error_max = 0.0;
      result_.stats.energy_work_approximate = drives_.any_work();
    }
  }

  // Records a frame; `effort` (drive efforts) may be null when torques are not reported
  // and no work is tracked. Returns false, recording nothing, if any value is not finite.
  bool Record(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
              const Eigen::VectorXd* effort) {
    if (!q.allFinite() || !qd.allFinite() || (effort && !effort->allFinite())) return false;
    ForwardKinematics(model_, data_, q);
    const Vector3d tcp =
        model_.tcp_frame >= 0 ? FramePosition(data_, model_.tcp_frame) : Vector3d::Zero();
    double kinetic = 0.0, potential = 0.0;
    if (result_.has_energy) {
      potential = PotentialEnergy(model_, data_);
      kinetic = KineticEnergy(model_, data_, q, qd);
      if (!std::isfinite(kinetic) || !std::isfinite(potential)) return false;
    }
    result_.t.push_back(t);
    result_.q.insert(result_.q.end(), q.data(), q.data() + q.size());
    result_.qd.insert(result_.qd.end(), qd.data(), qd.data() + qd.size());
    result_.tcp.insert(result_.tcp.end(), tcp.data(), tcp.data() + 3);
    if (result_.has_torques) {
      result_.tau.insert(result_.tau.end(), effort->data(), effort->data() + effort->size());
    }
    if (result_.has_energy) {
      result_.kinetic.push_back(kinetic);
      result_.potential.push_back(potential);
      TrackEnergy(t, kinetic + potential, qd, effort);
    }
    if (track_tcp_error_) TrackTcpError(t, tcp);
    result_.stats.t_reached = t;
    return true;
  }

 private:
  // |E(t) - E(0) - W(t)| relative to the energy scale, W = work of drives and damping
  // (trapezoid rule over the output samples).
  void TrackEnergy(double t, double energy, const Eigen::VectorXd& qd,
                   const Eigen::VectorXd* effort) {
    double power = 0.0;
    for (int i = 0; i < drives_.size(); ++i) {
      const double drive = effort ? (*effort)(i) : 0.0;
      power += (drive - drives_.damping(i) * qd(i)) * qd(i);
    }
    if (result_.t.size() == 1) {
      energy0_ = energy;
    } else {
      work_ += 0.5 * (power + last_power_) * (t - last_t_);
    }
    last_power_ = power;
    last_t_ = t;
    scale_ = std::max({scale_, std::abs(energy0_), std::abs(energy)});
    const double error = std::abs(energy - energy0_ - work_) / std::max(scale_, 1e-300);
    result_.stats.energy_error_max = std::max(result_.stats.energy_error_max, error);
  }

  void TrackTcpError(double t, const Vector3d& tcp) {
    for (int i = 0; i < drives_.size(); ++i) q_ref_(i) = drives_.Reference(i, t).q;
    ForwardKinematics(model_, data_, q_ref_);
    const double error = (tcp - FramePosition(data_, model_.tcp_frame)).norm();
    result_.stats.tcp_error_max = std::max(result_.stats.tcp_error_max, error);
  }

  const Model& model_;
  const DriveSet& drives_;
  RunResult& result_;
  Data data_;
  Eigen::VectorXd q_ref_;
  const bool track_tcp_error_;
  double energy0_ = 0.0, work_ = 0.0, last_power_ = 0.0, last_t_ = 0.0, scale_ = 0.0;
};

// The initial state y0 = [q0; qd0]: the spec's values, prescribed joints on their track.
Eigen::VectorXd InitialState(const RunConfig& config, const DriveSet& drives, int n) {
  Eigen::VectorXd y = Eigen::VectorXd::Zero(2 * n);
  if (config.q0.size() == n) y.head(n) = config.q0;
  if (config.qd0.size() == n) y.tail(n) = config.qd0;
  for (int i = 0; i < n; ++i) {
    if (!drives.prescribed(i)) continue;
    const TrajectoryPoint ref = drives.Reference(i, 0.0);
    if (!drives.velocity_source(i) || config.q0.size() != n) y(i) = ref.q;
    y(n + i) = ref.qd;
  }
  return y;
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
  Eigen::VectorXd y = InitialState(config, drives, n);
  std::unique_ptr<Integrator> integrator =
      MakeIntegrator(ode, 0.0, y.data(), IntegratorOptionsFrom(config, times.back()));
  result.stats.integrator = integrator->name();
  const bool need_effort = result.has_torques || result.has_energy;
  for (size_t k = 0; k < times.size(); ++k) {
    if (cancel && cancel->load(std::memory_order_relaxed)) {
      result.stats.status = RunStatus::kCancelled;
      result.stats.message = "cancelled at t = " + std::to_string(result.stats.t_reached) + " s";
      break;
    }
    if (k > 0) {
      const AdvanceResult advance = integrator->AdvanceTo(times[k], y.data());
      if (advance.status != IntegratorStatus::kOk) {
        result.stats.status = ToRunStatus(advance.status);
        result.stats.message = advance.message;
        break;
      }
    }
    const bool finite = ode.Evaluate(times[k], y.data());
    if (need_effort) ode.ComputePrescribedEfforts();
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

const char* RunStatusName(RunStatus status) {
  switch (status) {
    case RunStatus::kFinished:
      return "FINISHED";
    case RunStatus::kDiverged:
      return "DIVERGED";
    case RunStatus::kTooMuchWork:
      return "TOO_MUCH_WORK";
    case RunStatus::kErrorTestFailures:
      return "ERROR_TEST_FAILURES";
    case RunStatus::kConvergenceFailures:
      return "CONVERGENCE_FAILURES";
    case RunStatus::kFailed:
      return "FAILED";
    case RunStatus::kCancelled:
      return "CANCELLED";
  }
  return "FAILED";
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
  FrameRecorder recorder(model, drives, result, times.size(), /*track_tcp_error=*/!kinematic);
  if (kinematic) {
    RunKinematic(model, config, drives, times, recorder, result, sink, cancel);
  } else {
    RunJointSpace(model, config, drives, times, recorder, result, sink, cancel);
  }
  result.stats.cpu_s = ThreadCpuSeconds() - cpu0;
  result.stats.wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return result;
}

}  // namespace mbstream

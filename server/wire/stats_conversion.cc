#include "server/wire/stats_conversion.h"

#include <cmath>

namespace mbstream {

namespace {

double FiniteOr(double value, double fallback) { return std::isfinite(value) ? value : fallback; }

}  // namespace

v1::RunState RunStateFromStatus(RunStatus status) {
  switch (status) {
    case RunStatus::kFinished:
      return v1::FINISHED;
    case RunStatus::kDiverged:
      return v1::DIVERGED;
    case RunStatus::kTooMuchWork:
      return v1::TOO_MUCH_WORK;
    case RunStatus::kErrorTestFailures:
      return v1::ERROR_TEST_FAILURES;
    case RunStatus::kConvergenceFailures:
      return v1::CONVERGENCE_FAILURES;
    case RunStatus::kFailed:
      return v1::FAILED;
    case RunStatus::kCancelled:
      return v1::CANCELLED;
    case RunStatus::kInterrupted:
      return v1::INTERRUPTED;
  }
  return v1::FAILED;
}

bool IsFinalState(v1::RunState state) {
  return state != v1::RUN_STATE_UNSPECIFIED && state != v1::QUEUED && state != v1::RUNNING;
}

void SummaryToProto(const RunSummary& s, v1::RunSummary* out) {
  out->set_keep(s.keep);
  out->set_frames_computed(s.frames_computed);
  out->set_frames_kept(s.frames_kept);
  out->set_t_final_s(FiniteOr(s.t_final, 0.0));
  for (const double q : s.q_final) out->add_q_final(FiniteOr(q, 0.0));
  for (const double qd : s.qd_final) out->add_qd_final(FiniteOr(qd, 0.0));
  for (const JointSummary& joint : s.joints) {
    v1::JointSummary& j = *out->add_joints();
    // An effort too large to square has no finite RMS: its peak is the figure that matters.
    j.set_effort_peak(FiniteOr(joint.effort_peak, -1.0));
    j.set_effort_rms(FiniteOr(joint.effort_rms, joint.effort_peak < 0.0 ? -1.0 : j.effort_peak()));
    j.set_tracking_error_max(FiniteOr(joint.tracking_error_max, -1.0));
  }
}

RunSummary SummaryFromProto(const v1::RunSummary& in) {
  RunSummary s;
  s.keep = in.keep();
  s.frames_computed = in.frames_computed();
  s.frames_kept = in.frames_kept();
  s.t_final = in.t_final_s();
  s.q_final.assign(in.q_final().begin(), in.q_final().end());
  s.qd_final.assign(in.qd_final().begin(), in.qd_final().end());
  for (const v1::JointSummary& j : in.joints()) {
    s.joints.push_back({j.effort_peak(), j.effort_rms(), j.tracking_error_max()});
  }
  return s;
}

v1::RunStats StatsToProto(const RunStats& s) {
  v1::RunStats out;
  out.set_formulation(s.formulation);
  out.set_formulation_reason(s.formulation_reason);
  out.set_equations(s.equations);
  out.set_jacobian_nnz(s.jacobian_nnz);
  out.set_method(s.method);
  out.set_integrator(s.integrator);
  out.set_steps(s.solver.steps);
  out.set_rhs_evals(s.solver.rhs_evals);
  out.set_jac_evals(s.solver.jac_evals);
  out.set_nonlinear_iterations(s.solver.nonlinear_iterations);
  out.set_error_test_failures(s.solver.error_test_failures);
  out.set_convergence_failures(s.solver.convergence_failures);
  out.set_last_step_s(FiniteOr(s.solver.last_step, 0.0));
  out.set_last_order(s.solver.last_order);
  out.set_cpu_s(FiniteOr(s.cpu_s, 0.0));
  out.set_wall_s(FiniteOr(s.wall_s, 0.0));
  out.set_t_reached_s(FiniteOr(s.t_reached, 0.0));
  out.set_tcp_error_max_m(FiniteOr(s.tcp_error_max, -1.0));
  out.set_energy_error_max(FiniteOr(s.energy_error_max, -1.0));
  out.set_energy_work_approximate(s.energy_work_approximate);
  out.set_energy_work(s.energy_work);
  if (s.target_met) out.set_target_met(*s.target_met);
  out.set_choice_json(s.choice_json);
  out.set_drift_position_max_m(FiniteOr(s.drift_position_max, -1.0));
  out.set_drift_orientation_max_rad(FiniteOr(s.drift_orientation_max, -1.0));
  out.set_drift_velocity_max(FiniteOr(s.drift_velocity_max, -1.0));
  out.set_quaternion_norm_error_max(FiniteOr(s.quaternion_norm_error_max, -1.0));
  out.set_trust(TrustName(s.trust));
  out.set_trust_reason(s.trust_reason);
  out.set_max_steps(s.max_steps);
  out.set_max_cpu_s(FiniteOr(s.max_cpu_s, 0.0));
  if (!s.loops.cut_joints.empty()) {
    v1::LoopStats& loops = *out.mutable_loops();
    for (const std::string& joint : s.loops.cut_joints) loops.add_cut_joints(joint);
    loops.set_equations(s.loops.equations);
    loops.set_independent(s.loops.independent);
    loops.set_mobility(s.loops.mobility);
    loops.set_assembly(s.loops.assembly);
  }
  if (s.contact.active) {
    v1::ContactStats& contact = *out.mutable_contact();
    contact.set_penetration_max_m(FiniteOr(s.contact.penetration_max_m, 0.0));
    contact.set_contacts_peak(s.contact.contacts_peak);
    contact.set_penetration_relative_max(FiniteOr(s.contact.penetration_relative_max, 0.0));
    contact.set_dissipated_work_j(FiniteOr(s.contact.dissipated_work_j, 0.0));
  }
  SummaryToProto(s.summary, out.mutable_summary());
  return out;
}

RunStats StatsFromProto(const v1::RunInfo& info) {
  const v1::RunStats& in = info.stats();
  RunStats s;
  switch (info.state()) {
    case v1::FINISHED:
      s.status = RunStatus::kFinished;
      break;
    case v1::DIVERGED:
      s.status = RunStatus::kDiverged;
      break;
    case v1::TOO_MUCH_WORK:
      s.status = RunStatus::kTooMuchWork;
      break;
    case v1::ERROR_TEST_FAILURES:
      s.status = RunStatus::kErrorTestFailures;
      break;
    case v1::CONVERGENCE_FAILURES:
      s.status = RunStatus::kConvergenceFailures;
      break;
    case v1::CANCELLED:
      s.status = RunStatus::kCancelled;
      break;
    case v1::INTERRUPTED:
      s.status = RunStatus::kInterrupted;
      break;
    default:
      s.status = RunStatus::kFailed;
      break;
  }
  s.message = info.message();
  s.t_reached = in.t_reached_s();
  s.formulation = in.formulation();
  s.formulation_reason = in.formulation_reason();
  s.equations = in.equations();
  s.jacobian_nnz = in.jacobian_nnz();
  s.method = in.method();
  s.integrator = in.integrator();
  s.solver.steps = in.steps();
  s.solver.rhs_evals = in.rhs_evals();
  s.solver.jac_evals = in.jac_evals();
  s.solver.nonlinear_iterations = in.nonlinear_iterations();
  s.solver.error_test_failures = in.error_test_failures();
  s.solver.convergence_failures = in.convergence_failures();
  s.solver.last_step = in.last_step_s();
  s.solver.last_order = in.last_order();
  s.cpu_s = in.cpu_s();
  s.wall_s = in.wall_s();
  s.tcp_error_max = in.tcp_error_max_m();
  s.energy_error_max = in.energy_error_max();
  s.energy_work_approximate = in.energy_work_approximate();
  s.energy_work = in.energy_work();
  if (in.has_target_met()) s.target_met = in.target_met();
  s.choice_json = in.choice_json();
  s.drift_position_max = in.drift_position_max_m();
  s.drift_orientation_max = in.drift_orientation_max_rad();
  s.drift_velocity_max = in.drift_velocity_max();
  s.quaternion_norm_error_max = in.quaternion_norm_error_max();
  s.trust = in.trust() == "ok"    ? Trust::kOk
            : in.trust() == "low" ? Trust::kLow
                                  : Trust::kNotAssessed;
  s.trust_reason = in.trust_reason();
  s.max_steps = in.max_steps();
  s.max_cpu_s = in.max_cpu_s();
  if (in.has_loops()) {
    s.loops.cut_joints.assign(in.loops().cut_joints().begin(), in.loops().cut_joints().end());
    s.loops.equations = in.loops().equations();
    s.loops.independent = in.loops().independent();
    s.loops.mobility = in.loops().mobility();
    s.loops.assembly = in.loops().assembly();
  }
  if (in.has_contact()) {
    s.contact = {true, in.contact().penetration_max_m(), in.contact().contacts_peak(),
                 in.contact().penetration_relative_max(), in.contact().dissipated_work_j()};
  }
  if (in.has_summary()) s.summary = SummaryFromProto(in.summary());
  s.warnings.assign(info.warnings().begin(), info.warnings().end());
  return s;
}

}  // namespace mbstream

#include "server/sim/run_trust.h"

#include <string>

#include "common/format.h"
#include "server/integrate/failure_messages.h"

namespace mbstream {

namespace {

// Appends "what = value (limit)" to `reason` when value > limit.
bool Exceeds(double value, double limit, const char* what, std::string* reason) {
  if (!(value > limit)) return false;
  if (!reason->empty()) *reason += "; ";
  *reason += FormatString("%s %.3g exceeds %g", what, value, limit);
  return true;
}

}  // namespace

void AssessTrust(RunStats* s) {
  s->trust_reason.clear();
  if (s->status != RunStatus::kFinished) {
    s->trust = Trust::kNotAssessed;
    return;
  }
  // Two remedies: a failed indicator of the integration asks for tighter tolerances or a
  // smaller step; an energy balance whose work is a trapezoid rule over the output frames
  // carries that rule's error, which only a smaller output interval reduces.
  std::string reason;
  bool integration = false;
  const bool frame_work = s->energy_work_approximate;
  const bool energy =
      Exceeds(s->energy_error_max, frame_work ? kTrustEnergyErrorApproximate : kTrustEnergyError,
              "energy balance error", &reason);
  integration |= energy && !frame_work;
  integration |=
      Exceeds(s->tcp_error_max, kTrustTcpError, "TCP error (m) against the closed form", &reason);
  integration |=
      Exceeds(s->drift_position_max, kTrustDriftPosition, "constraint drift (m)", &reason);
  integration |=
      Exceeds(s->drift_orientation_max, kTrustDriftOrientation, "constraint drift (rad)", &reason);
  integration |=
      Exceeds(s->quaternion_norm_error_max, kTrustQuaternionNorm, "quaternion norm error", &reason);
  if (s->solver.steps > 0) {
    const double rejected =
        static_cast<double>(s->solver.error_test_failures) / static_cast<double>(s->solver.steps);
    integration |=
        Exceeds(rejected, kTrustRejectedPerStep, "rejected steps per accepted step", &reason);
  }
  s->trust = reason.empty() ? Trust::kOk : Trust::kLow;
  if (reason.empty()) return;
  std::string remedy;
  if (energy && frame_work) {
    // A tree run may switch to the joint formulation, which integrates the work; a run with
    // closed loops (loop_run.h) has no such formulation.
    const bool tree = s->loops.cut_joints.empty();
    remedy = FormatString(
        "the work of drives and damping is the trapezoid rule over the output frames (formulation "
        "%s), whose error the energy balance includes: use a smaller output_interval_s%s",
        s->formulation.c_str(),
        tree ? ", or the joint formulation, which integrates the work with the motion" : "");
  }
  if (integration) {
    if (!remedy.empty()) remedy += "; and ";
    remedy += "tighten rtol/atol or use a smaller step (--step) or an adaptive method";
  }
  s->trust_reason = reason + ": the result cannot be trusted; " + remedy;
}

}  // namespace mbstream

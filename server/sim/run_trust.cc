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
  std::string reason;
  const double energy_limit =
      s->energy_work_approximate ? kTrustEnergyErrorApproximate : kTrustEnergyError;
  Exceeds(s->energy_error_max, energy_limit, "energy balance error", &reason);
  Exceeds(s->tcp_error_max, kTrustTcpError, "TCP error (m) against the closed form", &reason);
  Exceeds(s->drift_position_max, kTrustDriftPosition, "constraint drift (m)", &reason);
  Exceeds(s->drift_orientation_max, kTrustDriftOrientation, "constraint drift (rad)", &reason);
  Exceeds(s->quaternion_norm_error_max, kTrustQuaternionNorm, "quaternion norm error", &reason);
  if (s->solver.steps > 0) {
    const double rejected =
        static_cast<double>(s->solver.error_test_failures) / static_cast<double>(s->solver.steps);
    Exceeds(rejected, kTrustRejectedPerStep, "rejected steps per accepted step", &reason);
  }
  s->trust = reason.empty() ? Trust::kOk : Trust::kLow;
  if (!reason.empty()) {
    s->trust_reason = reason +
                      ": the result cannot be trusted; tighten rtol/atol or use a smaller step "
                      "(--step) or an adaptive method";
  }
}

}  // namespace mbstream

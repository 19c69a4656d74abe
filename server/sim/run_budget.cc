#include "server/sim/run_budget.h"

#include <algorithm>
#include <cmath>

#include "server/integrate/failure_messages.h"
#include "shared/common/format.h"

namespace mbstream {

long DefaultMaxSteps(double duration_s) {
  const double steps =
      static_cast<double>(kStepBudgetFloor) + kStepsPerSimulatedSecond * std::max(0.0, duration_s);
  // A duration the server accepts (<= days) stays far below this; clamp for safety.
  return static_cast<long>(std::min(steps, 2.0e9));
}

double DefaultMaxCpuSeconds(double duration_s, int num_dofs) {
  const double per_arm = static_cast<double>(num_dofs) / 6.0;
  const double size = std::max(1.0, per_arm * per_arm);
  return kCpuBudgetFloorS + kCpuPerSimulatedSecondS * std::max(0.0, duration_s) * size;
}

void ResolveBudget(int num_dofs, RunConfig* config) {
  if (config->max_steps <= 0) config->max_steps = DefaultMaxSteps(config->duration);
  if (!(config->max_cpu_s > 0.0)) {
    config->max_cpu_s = DefaultMaxCpuSeconds(config->duration, num_dofs);
  }
}

std::string BudgetMessage(const RunConfig& config, const BudgetReport& r) {
  const double rate = r.t_reached > 0.0 ? static_cast<double>(r.steps) / r.t_reached : 0.0;
  std::string text;
  if (r.cpu) {
    text = FormatString("budget exhausted: %.3g s of CPU (max_cpu_s = %g s) used", r.cpu_s,
                        config.max_cpu_s);
  } else {
    text = FormatString("budget exhausted: %ld internal steps (max_internal_steps = %ld) used",
                        r.steps, config.max_steps);
  }
  text += FormatString(" by t = %.6g s of %g s", r.t_reached, r.duration);
  if (rate > 0.0) {
    text += FormatString(
        ", at %.3g steps per simulated second (the default budget allows %.3g; "
        "last step %.3g s)",
        rate, kStepsPerSimulatedSecond, r.last_step);
  } else {
    text += FormatString(" (last step %.3g s)", r.last_step);
  }
  if (r.causes.empty()) {
    text +=
        "; no input looks wrong: the scene may need that much work (raise max_internal_steps "
        "or max_cpu_s in the spec) or a cheaper setting (a looser rtol, method bdf for a "
        "stiff scene)";
  } else {
    text += "; likely cause: " + r.causes.front();
    for (size_t i = 1; i < r.causes.size() && i < 3; ++i) text += "; also " + r.causes[i];
  }
  text += r.advice;
  text += "; the frames up to the stop are kept";
  return text;
}

}  // namespace mbstream

#include "server/runs/run_budget_caps.h"

#include <algorithm>

#include "server/integrate/failure_messages.h"
#include "server/sim/input_sanity.h"
#include "server/sim/run_budget.h"
#include "shared/common/format.h"

namespace mbstream {

std::vector<std::string> PrepareRunBudget(const Model& model, const ServerLimits& limits,
                                          RunConfig* config) {
  std::vector<std::string> warnings = WarningMessages(CheckInputSanity(model, *config));
  const bool steps_asked = config->max_steps > 0;
  const bool cpu_asked = config->max_cpu_s > 0.0;
  ResolveBudget(model.num_dofs(), config);
  if (config->max_steps > limits.max_internal_steps) {
    if (steps_asked) {
      warnings.push_back(
          FormatString("max_internal_steps = %ld exceeds this server's cap of %ld steps "
                       "(mbstream-server --max-run-steps): the run gets %ld",
                       config->max_steps, limits.max_internal_steps, limits.max_internal_steps));
    }
    config->max_steps = limits.max_internal_steps;
  }
  if (config->max_cpu_s > limits.max_run_cpu_s) {
    if (cpu_asked) {
      warnings.push_back(
          FormatString("max_cpu_s = %g s exceeds this server's cap of %g s (mbstream-server "
                       "--max-run-cpu-s): the run gets %g s",
                       config->max_cpu_s, limits.max_run_cpu_s, limits.max_run_cpu_s));
    }
    config->max_cpu_s = limits.max_run_cpu_s;
  }
  return warnings;
}

}  // namespace mbstream

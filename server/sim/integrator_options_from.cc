#include "server/sim/integrator_options_from.h"

namespace mbstream {

IntegratorOptions IntegratorOptionsFrom(const RunConfig& config, double t_final,
                                        double cpu_deadline_s) {
  IntegratorOptions options;
  options.method = config.method;
  options.rtol = config.rtol;
  options.atol = config.atol;
  options.max_step = config.max_step;
  options.fixed_step = config.fixed_step;
  options.erk_table = config.erk_table;
  if (config.max_steps > 0) options.max_steps = config.max_steps;
  options.t_final = t_final;
  options.cpu_deadline_s = cpu_deadline_s;
  return options;
}

}  // namespace mbstream

// Maps a run's configuration to the integrator's options: the edge between the run (sim)
// and the integration layer, which knows nothing of runs.
#pragma once

#include <limits>

#include "server/integrate/integrator.h"
#include "server/sim/run_config.h"

namespace mbstream {

// The options of a run: RunConfig's solver fields, with the given stop time and CPU deadline
// (RunConfig::max_steps 0 keeps IntegratorOptions' default step budget).
IntegratorOptions IntegratorOptionsFrom(
    const RunConfig& config, double t_final,
    double cpu_deadline_s = std::numeric_limits<double>::infinity());

}  // namespace mbstream

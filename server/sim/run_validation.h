// The one validation of a run request against its model: everything that would make the run
// fail for a reason knowable before it starts (formulation, method, Butcher table, options,
// body formulations' requirements). The service calls it before queueing a run, the CLI's
// `simulate` before simulating, and Simulate itself, so a request it accepts does not fail
// with an InputError inside a worker.
#pragma once

#include "server/drives/drive_set.h"
#include "server/model/model.h"
#include "server/sim/formulation_choice.h"
#include "server/sim/run_config.h"

namespace mbstream {

// Validates `config` (converted and range-checked by server/spec) for `model` and returns the
// formulation the run will use. Throws InputError saying what is wrong and what to give
// instead.
FormulationChoice ValidateRun(const Model& model, const RunConfig& config);

// The same with the run's drives already built (Simulate's path: no second DriveSet).
FormulationChoice ValidateRun(const Model& model, const RunConfig& config, const DriveSet& drives);

}  // namespace mbstream

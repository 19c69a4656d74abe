// A run's budget on this server: the spec's budget (or the default for the run's duration
// and model) clamped to the server's caps (mbstream-server --max-run-steps,
// --max-run-cpu-s), and the warnings the run starts with.
#pragma once

#include <string>
#include <vector>

#include "server/model/model.h"
#include "server/runs/server_limits.h"
#include "server/sim/run_config.h"

namespace mbstream {

// Resolves config's budget (ResolveBudget) and clamps it to `limits`. Returns the run's
// warnings: the inputs' sanity warnings (CheckInputSanity) and one for each budget the spec
// asked for beyond the server's cap.
std::vector<std::string> PrepareRunBudget(const Model& model, const ServerLimits& limits,
                                          RunConfig* config);

}  // namespace mbstream

// Which formulation a run uses, and why: "model no more than a scene needs".
#pragma once

#include <string>

#include "server/drives/drive_set.h"
#include "server/sim/run_config.h"

namespace mbstream {

struct FormulationChoice {
  Formulation formulation = Formulation::kJoint;
  std::string reason;  // one sentence for the user, e.g. why auto chose it
};

// Resolves config.formulation (kAuto included) for these drives. Throws InputError when the
// requested formulation cannot answer the run (kinematic with a joint that is not
// prescribed; a body formulation with a method of the wrong kind) or is not available, with
// what to use instead.
FormulationChoice ChooseFormulation(const RunConfig& config, const DriveSet& drives);

}  // namespace mbstream

// The one validation of a run request against its model: everything that would make the run
// fail for a reason knowable before it starts (formulation, method, Butcher table, options,
// body formulations' requirements). It runs once per request, at the door: the service before
// queueing a run, the CLI's `simulate` after reading the spec (for a model with closed loops
// through ValidateLoopRun, loop_run.h). The layers inside (the engine, the choice of method)
// rely on it and only CHECK what they need (ValidatedFormulation), so a request it accepts does
// not fail with an InputError inside a worker.
#pragma once

#include <string>

#include "server/drives/drive_set.h"
#include "server/model/model.h"
#include "server/sim/formulation_choice.h"
#include "server/sim/run_config.h"

namespace mbstream {

// Validates `config` (converted and range-checked by server/spec) for `model` and returns the
// formulation the run will use. Throws InputError saying what is wrong and what to give
// instead.
FormulationChoice ValidateRun(const Model& model, const RunConfig& config);

// The same with the run's drives already built (ValidateLoopRun's path: no second DriveSet).
FormulationChoice ValidateRun(const Model& model, const RunConfig& config, const DriveSet& drives);

// For a config ValidateRun accepted: the formulation it runs with. CHECKs the shape the
// engine indexes by (one drive per joint, a positive finite duration and output interval); a
// failure is a caller that skipped ValidateRun, a bug (InternalError), not a user's error.
FormulationChoice ValidatedFormulation(const Model& model, const RunConfig& config,
                                       const DriveSet& drives);

// Throws InputError "free joint 'NAME' (link 'LINK') [and N more]: <what>" when `model` has
// free bodies (JointType::kFree); nothing otherwise.
void RefuseFreeBodies(const Model& model, const std::string& what);

// Throws InputError "ball joint 'NAME' (link 'LINK') [and N more]: <what>" when `model` has
// ball joints (JointType::kBall); nothing otherwise.
void RefuseBallJoints(const Model& model, const std::string& what);

// A run of a model with ball joints: refuses what does not simulate them yet (the body
// formulations, kinematic, accuracy targets), a drive on a ball joint's coordinate,
// initial_q or initial_qd of the wrong length and an initial quaternion whose norm is not 1
// within 1e-6, naming the norm. ValidateRun calls it; closed loops refuse ball joints in the
// tree in ValidateLoopRun.
void CheckBallJoints(const Model& model, const RunConfig& config);

// A run of a model with free bodies: refuses what does not simulate them yet (the body
// formulations, accuracy targets), a drive on a free joint's coordinate, initial_q or
// initial_qd of the wrong length (nq and nv values: model.h) and an initial quaternion whose
// norm is not 1 within 1e-6, naming the norm. ValidateRun calls it; closed loops refuse free
// bodies in ValidateLoopRun.
void CheckFreeBodies(const Model& model, const RunConfig& config);

// A run with sampled drives (external, pd_servo with a period: drive_set.h): refuses what
// does not run them yet (formulations other than joint, accuracy targets, free bodies); with
// contact they run (the states carry the contacts: control_law.h).
// ValidateRun calls it; closed loops refuse sampled drives in ValidateLoopRun.
void CheckSampledDrives(const Model& model, const RunConfig& config, const DriveSet& drives,
                        const FormulationChoice& choice);

// ValidatedFormulation's CHECKs alone.
void CheckValidatedShape(const Model& model, const RunConfig& config);

}  // namespace mbstream

// URDF <mimic joint="LEADER" multiplier="m" offset="o"/> inside a moving joint: the joint
// follows LEADER, q = m * q(LEADER) + o (rad or m; multiplier 1 and offset 0 when absent).
//
// Coupled (UrdfImportOptions::couple_mimic, `mbstream submit/simulate --couple-mimic`), each
// becomes a LoopClosure of type kMimic (server/model/loop_closure.h): one equation on the
// joint coordinates that the closed-loop runs hold, as they hold a cut joint's. Not coupled
// (the default, as MuJoCo's and Gazebo's URDF readers do), the joint moves as a degree of
// freedom of its own, with a warning saying how to couple it (a fixed joint's <mimic>: a
// warning to remove it).
//
// Errors (InputError, "FILE:LINE: joint 'NAME': ..."), coupled only: a <mimic> on a fixed
// joint, a leader that is not a moving joint of the model or is the joint itself, a
// non-finite multiplier or offset.
#pragma once

#include <memory>
#include <vector>

#include <urdf_model/joint.h>

#include "server/model/loop_closure.h"
#include "server/model/model.h"
#include "server/parse/urdf_diagnostics.h"

namespace mbstream {

// The couplings of `joints` (in their order) on `model`, built from them; empty with a
// warning per <mimic> when `couple` is false.
std::vector<LoopClosure> MimicCouplings(const std::vector<urdf::JointConstSharedPtr>& joints,
                                        const Model& model, bool couple,
                                        const UrdfDiagnostics& diagnostics);

}  // namespace mbstream

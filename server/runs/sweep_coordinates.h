// A sweep over one coordinate of the initial state: `initial_q[NAME]` and `initial_qd[NAME]`
// take the names of ModelInfo.position_names and velocity names (a free body's box::link.z,
// a joint's joint2), and a base spec without initial_q (or initial_qd) starts from the model's
// own (NeutralPositions: zeros, each free body at its model pose; zero velocities), so that
// one coordinate is swept and the others keep their defaults.
#pragma once

#include <string>
#include <vector>

#include "mbstream/v1/sweep.pb.h"
#include "server/model/model.h"

namespace mbstream {

// Rewrites `definition`'s paths `initial_q[NAME]` / `initial_qd[NAME]` to their indices and
// fills an absent base initial_q / initial_qd when a path indexes it. Throws InputError naming
// the path and the closest coordinate name when NAME is unknown.
void ResolveCoordinatePaths(const Model& model, v1::SweepDefinition* definition);

}  // namespace mbstream

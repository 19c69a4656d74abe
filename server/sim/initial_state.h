// A run's initial joint state.
#pragma once

#include <Eigen/Core>

#include "server/drives/drive_set.h"
#include "server/model/model.h"
#include "server/sim/run_config.h"

namespace mbstream {

// y0 = [q0; qd0] (2n): the spec's values, prescribed joints on their track (a velocity
// source keeps the spec's q0 when it gives one).
Eigen::VectorXd InitialJointState(const RunConfig& config, const DriveSet& drives, int n);

// The same for `model`, with free bodies too: y0 = [q0 (nq); qd0 (nv)], q0 the spec's
// (config.q0, nq values) or the neutral positions (NeutralPositions: each free body at its
// default pose), then config.initial_bodies over them (initial_bodies.h), every free body's
// quaternion normalised (ValidateRun refused one that was not unit within 1e-6). Without free
// bodies InitialJointState(config, drives, model.nv()).
Eigen::VectorXd InitialJointState(const RunConfig& config, const DriveSet& drives,
                                  const Model& model);

}  // namespace mbstream

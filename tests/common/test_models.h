// Models built in code for the physics tests (independent of the URDF importer).
#pragma once

#include <random>

#include <Eigen/Core>

#include "server/model/model.h"

namespace mbstream::testing {

// The IRB 1600 kinematics of the seed (models/irb1600/irb1600.urdf) with plausible made-up
// inertias, a named point "tcp" at (0.065, 0, 0) in link6; armature and damping zero.
Model Irb1600Model();

// A 7-joint arm (revolute z, y, z, y, z, y, x) of other proportions and masses than the
// IRB 1600 (12, 9, 7, 5, 3, 1.5, 0.4 kg), with a named point "tcp" 0.1 m beyond the last
// joint: a model the accuracy-target choice was not developed on.
Model SevenJointArm();

// A branching tree with revolute and prismatic joints about skew axes, fixed links and
// armature: exercises everything the algorithms support.
Model BranchingModel();

// One rigid body on a revolute joint about y at the origin: mass m (kg) at (0, 0, -l) m,
// rotational inertia about its centre of mass diag(i_cm, i_cm, i_cm) kg*m^2.
Model SinglePendulum(double m, double l, double i_cm);

// A uniformly random vector in [-scale, scale]^n, from a fixed-seed generator.
Eigen::VectorXd RandomVector(std::mt19937& rng, int n, double scale);

}  // namespace mbstream::testing

// The algorithms for a model with free bodies or ball joints (Model::has_quaternions):
// positions indexed by Body::q_index, velocities and forces by Body::v_index, a free joint's
// six columns from server/kinematics/free_joint.h, a ball joint's three from ball_joint.h,
// every other joint through the general (unspecialised) transforms. The public entries (Aba,
// HybridAba, Rnea, Crba, the energies, forward kinematics) call these when the model has
// quaternions and keep their specialised paths for trees without them, which so pay one test
// per call. Internal to server/dynamics. Allocate nothing.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "server/model/data.h"
#include "server/model/model.h"

namespace mbstream::free_tree {

using ConstVector = const Eigen::Ref<const Eigen::VectorXd>&;

// data.X_parent, data.v and data.c (the velocity-product accelerations) of every body.
void Velocities(const Model& model, Data& data, ConstVector q, ConstVector qd);

// Rnea (rnea.h) into data.tau.
const Eigen::VectorXd& Rnea(const Model& model, Data& data, ConstVector q, ConstVector qd,
                            ConstVector qdd);

// Aba (aba.h) into data.qdd: the fixed-base trees' specialised passes for every body but the
// free roots (free_aba.cc).
const Eigen::VectorXd& Aba(const Model& model, Data& data, ConstVector q, ConstVector qd,
                           ConstVector tau);

// HybridAba (hybrid_dynamics.h); `prescribed` null (no velocity coordinate prescribed: Aba)
// or nv flags. A free or ball joint's coordinates are never prescribed (the run's validation
// refuses drives on them): CHECKed.
const Eigen::VectorXd& HybridAba(const Model& model, Data& data, ConstVector q, ConstVector qd,
                                 ConstVector tau, ConstVector qdd,
                                 const std::vector<unsigned char>* prescribed);

// Crba (crba.h) into data.M.
const Eigen::MatrixXd& Crba(const Model& model, Data& data, ConstVector q);

// KineticEnergyAfterKinematics (energy.h): data.X_parent from the same q.
double KineticEnergy(const Model& model, Data& data, ConstVector qd);

}  // namespace mbstream::free_tree

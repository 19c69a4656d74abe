// Steps on the position manifold of a model with free bodies or ball joints (model.h): a
// velocity-space change dv (nv values) applied to positions q (nq values), q <- q (+) dv, as
// the integrators' q' = G(q) v would move q along dv for unit time at constant v, with each
// quaternion turned exactly (quat <- quat (x) exp(dw / 2), dw the rotation vector in the
// rotated frame) and renormalised. A one-coordinate joint's position moves by its dv; a free
// body's origin by its (world-frame) linear dv. The closed loops' Newton steps
// (loop_solver.h) correct q this way: their Jacobian G has nv columns, so a correction is a
// velocity-space vector. Allocate nothing.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "server/model/model.h"

namespace mbstream {

// q <- q (+) (scale * dv). Without quaternions q += scale * dv.
void StepPositions(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& dv, double scale,
                   Eigen::Ref<Eigen::VectorXd> q);

// Per velocity coordinate, the index of its joint's position in q, or -1 for a free or ball
// joint's coordinates (their positions are quaternions). Without quaternions: 0, 1, ... nv-1.
// Allocates.
std::vector<int> PositionOfVelocity(const Model& model);

// Every quaternion of q (Model::quaternions) scaled to unit length.
void NormaliseQuaternions(const Model& model, Eigen::Ref<Eigen::VectorXd> q);

}  // namespace mbstream

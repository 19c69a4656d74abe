// The root functions of contact for the joint-space ODEs (JointSpaceOde, ClosedLoopOde: their
// OdeSystem::Roots): the signed distances of the contact's root pairs at a configuration.
#pragma once

#include <cmath>

#include <Eigen/Core>

#include "server/contact/contact_forces.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/model/data.h"
#include "server/model/model.h"

namespace mbstream {

// g[k] = the signed distance of root pair k at q (its quaternions unit), time t; codes as
// OdeSystem::Roots. A time or state that is not finite (CVODE has asked at t = inf after a
// failed first step) never reaches the narrow phase, whose library asserts on it: the root
// function fails (1), and with it the step, with a message; so does a distance that is not
// finite. Allocates nothing.
inline int ContactRoots(const Model& model, Data& data, ContactForces& contact, double t,
                        const Eigen::VectorXd& q, double* g) {
  if (!std::isfinite(t) || !q.allFinite()) return 1;
  BodyKinematics(model, data, q);
  contact.SignedDistances(data, g);
  for (int k = 0; k < contact.num_root_pairs(); ++k) {
    if (!std::isfinite(g[k])) return 1;
  }
  return 0;
}

}  // namespace mbstream

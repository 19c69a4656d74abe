// What contact needs of a formulation's state, whatever its coordinates: each body's pose in
// the world, the velocity of a material point, and where a force applied at a point goes. The
// joint-space formulations answer from Data and qd (JointContactBodies, point_forces.h: J^T f
// into the generalised forces); body coordinates answer from each body's pose and twist and
// take the force as a wrench on the body (server/body/body_contact.h).
#pragma once

#include <Eigen/Core>

#include "server/math/spatial.h"
#include "server/model/data.h"
#include "server/model/model.h"

namespace mbstream {

class ContactBodies {
 public:
  virtual ~ContactBodies() = default;
  // X_WB of a moving body (body >= 0): its link frame in the world.
  virtual const Pose& X_world(int body) const = 0;
  // The velocity (m/s, world) of the material point of `body` at world point p; 0 for kBase.
  virtual Vector3d PointVelocity(int body, const Vector3d& p) const = 0;
  // Applies force f (N, world) to `body` at world point p; nothing for kBase.
  virtual void AddPointForce(int body, const Vector3d& p, const Vector3d& f) = 0;
};

// The joint-space answer: poses from Data (after BodyKinematics or ForwardKinematics for q),
// velocities from qd, forces as J^T f added to *tau (nv values; may be null for a caller that
// only asks for poses). Allocates nothing.
class JointContactBodies : public ContactBodies {
 public:
  JointContactBodies(const Model& model, const Data& data, const Eigen::VectorXd* qd,
                     Eigen::VectorXd* tau)
      : model_(model), data_(data), qd_(qd), tau_(tau) {}
  const Pose& X_world(int body) const override { return data_.X_world[body]; }
  Vector3d PointVelocity(int body, const Vector3d& p) const override;
  void AddPointForce(int body, const Vector3d& p, const Vector3d& f) override;

 private:
  const Model& model_;
  const Data& data_;
  const Eigen::VectorXd* qd_;
  Eigen::VectorXd* tau_;
};

}  // namespace mbstream

// Contact in body coordinates (docs/contact.md): the contact forces of ContactForces acting on
// the bodies of a BodyMechanics. Each body's link frame comes from its centre-of-mass pose
// (origin x - R c), a material point's velocity from its twist (v + (R w) x r, r from the
// centre of mass), and a force F at point p becomes F on the centre of mass (base frame) and
// the torque R^T (r x F) (body frame): the applied force f of M dnu/dt = f + G^T lambda. The
// joint-space runs take the same forces as J^T F (point_forces.h).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "server/contact/contact_bodies.h"
#include "server/contact/contact_forces.h"

namespace mbstream {

class BodyMechanics;

class BodyContact : public ContactBodies {
 public:
  // Keeps references to both, which must outlive it. Allocates the poses once.
  BodyContact(const BodyMechanics& mechanics, ContactForces& forces);

  // After BodyMechanics::Load: the contacts at the loaded state, their forces added to *f
  // (6n: [force, base frame; torque about the centre of mass, body frame] per body). Returns
  // false when a force is not finite. Allocates nothing (as ContactForces::AddForces).
  bool AddTo(Eigen::VectorXd* f);
  // After BodyMechanics::Load: the signed distances of the root pairs (ContactForces::
  // SignedDistances, m). Allocates nothing.
  void Distances(double* g);

  // The power of the contact forces of the last AddTo on the bodies (W): the sum over points of
  // F . (v_a(p) - v_b(p)).
  double power() const { return power_; }
  const ContactForces& forces() const { return forces_; }
  ContactForces& forces() { return forces_; }

  const Pose& X_world(int body) const override { return X_[body]; }
  Vector3d PointVelocity(int body, const Vector3d& p) const override;
  void AddPointForce(int body, const Vector3d& p, const Vector3d& f) override;

 private:
  void LoadPoses();

  const BodyMechanics& mechanics_;
  ContactForces& forces_;
  std::vector<Pose> X_;           // each body's link frame in the world (base frame)
  Eigen::VectorXd* f_ = nullptr;  // AddTo's target
  double power_ = 0.0;
};

}  // namespace mbstream

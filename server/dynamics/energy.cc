#include "server/dynamics/energy.h"

#include "server/dynamics/free_tree.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/kinematics/joint_transform.h"
#include "shared/common/check.h"

namespace mbstream {

double KineticEnergy(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& q,
                     const Eigen::Ref<const Eigen::VectorXd>& qd) {
  if (model.has_quaternions()) {
    MBSTREAM_CHECK(q.size() == model.nq());
    BodyKinematics(model, data, q);
    return KineticEnergyAfterKinematics(model, data, qd);
  }
  const int n = model.num_bodies();
  MBSTREAM_CHECK(q.size() == n);
  for (int i = 0; i < n; ++i) JointTransform(model.bodies[i].joint, q(i), &data.X_parent[i]);
  return KineticEnergyAfterKinematics(model, data, qd);
}

double KineticEnergyAfterKinematics(const Model& model, Data& data,
                                    const Eigen::Ref<const Eigen::VectorXd>& qd) {
  if (model.has_quaternions()) {
    MBSTREAM_CHECK(qd.size() == model.nv());
    return free_tree::KineticEnergy(model, data, qd);
  }
  const int n = model.num_bodies();
  MBSTREAM_CHECK(qd.size() == n);
  double energy = 0.0;
  for (int i = 0; i < n; ++i) {
    const Body& body = model.bodies[i];
    data.v[i] = data.S[i] * qd(i);  // spatial velocity in the body frame
    if (body.parent != kBase) data.v[i] += MotionToChild(data.X_parent[i], data.v[body.parent]);
    energy += 0.5 * data.v[i].dot(body.inertia.Apply(data.v[i]));
    energy += 0.5 * body.joint.armature * qd(i) * qd(i);
  }
  return energy;
}

double PotentialEnergy(const Model& model, const Data& data) {
  double energy = 0.0;
  for (int i = 0; i < model.num_bodies(); ++i) {
    const RigidInertia& inertia = model.bodies[i].inertia;
    energy -= inertia.mass * model.gravity.dot(data.X_world[i].Apply(inertia.com));
  }
  return energy;
}

}  // namespace mbstream

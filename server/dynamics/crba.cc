#include "server/dynamics/crba.h"

#include "server/dynamics/free_tree.h"
#include "server/kinematics/joint_inertia_transform.h"
#include "server/kinematics/joint_transform.h"
#include "shared/common/check.h"

namespace mbstream {

const Eigen::MatrixXd& Crba(const Model& model, Data& data,
                            const Eigen::Ref<const Eigen::VectorXd>& q) {
  if (model.has_quaternions()) {
    MBSTREAM_CHECK(q.size() == model.nq());
    return free_tree::Crba(model, data, q);
  }
  const int n = model.num_bodies();
  MBSTREAM_CHECK(q.size() == n);
  for (int i = 0; i < n; ++i) {
    JointTransform(model.bodies[i].joint, q(i), &data.X_parent[i]);
    data.IA[i] = data.I[i];
  }
  for (int i = n - 1; i >= 0; --i) {
    const int parent = model.bodies[i].parent;
    if (parent != kBase) {
      AddInertiaAcrossJoint(model.bodies[i].joint, data.X_parent[i], data.IA[i], &data.IA[parent]);
    }
  }
  for (int i = 0; i < n; ++i) {
    Vector6d F = data.IA[i] * data.S[i];
    data.M(i, i) = data.S[i].dot(F) + model.bodies[i].joint.armature;
    for (int j = i; model.bodies[j].parent != kBase;) {
      F = ForceToParent(data.X_parent[j], F);
      j = model.bodies[j].parent;
      data.M(i, j) = data.M(j, i) = data.S[j].dot(F);
    }
  }
  return data.M;
}

}  // namespace mbstream

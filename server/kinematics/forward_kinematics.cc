#include "server/kinematics/forward_kinematics.h"

#include "common/check.h"
#include "server/kinematics/joint_transform.h"

namespace mbstream {

void ForwardKinematics(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& q) {
  BodyKinematics(model, data, q);
  for (size_t k = 0; k < model.frames.size(); ++k) {
    const Frame& frame = model.frames[k];
    data.frame_world[k] = frame.body == kBase ? frame.X_BF : data.X_world[frame.body] * frame.X_BF;
  }
}

void BodyKinematics(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& q) {
  MBSTREAM_CHECK(q.size() == model.num_dofs());
  for (int i = 0; i < model.num_dofs(); ++i) {
    const Body& body = model.bodies[i];
    JointTransform(body.joint, q(i), &data.X_parent[i]);
    data.X_world[i] =
        body.parent == kBase ? data.X_parent[i] : data.X_world[body.parent] * data.X_parent[i];
  }
}

}  // namespace mbstream

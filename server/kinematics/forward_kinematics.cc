#include "server/kinematics/forward_kinematics.h"

#include "server/kinematics/ball_joint.h"
#include "server/kinematics/free_joint.h"
#include "server/kinematics/joint_transform.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

// BodyKinematics for a model with free bodies or ball joints (q indexed by Body::q_index).
void FreeBodyKinematics(const Model& model, Data& data,
                        const Eigen::Ref<const Eigen::VectorXd>& q) {
  for (int i = 0; i < model.num_bodies(); ++i) {
    const Body& body = model.bodies[i];
    if (body.free()) {
      free_joint::Transform(q.data() + body.q_index, &data.X_parent[i]);
    } else if (body.ball()) {
      ball_joint::Transform(body.joint, q.data() + body.q_index, &data.X_parent[i]);
    } else {
      JointTransform(body.joint, q(body.q_index), &data.X_parent[i]);
    }
    data.X_world[i] =
        body.parent == kBase ? data.X_parent[i] : data.X_world[body.parent] * data.X_parent[i];
  }
}

}  // namespace

void ForwardKinematics(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& q) {
  BodyKinematics(model, data, q);
  for (size_t k = 0; k < model.frames.size(); ++k) {
    const Frame& frame = model.frames[k];
    data.frame_world[k] = frame.body == kBase ? frame.X_BF : data.X_world[frame.body] * frame.X_BF;
  }
}

void BodyKinematics(const Model& model, Data& data, const Eigen::Ref<const Eigen::VectorXd>& q) {
  MBSTREAM_CHECK(q.size() == model.nq());
  if (model.has_quaternions()) {
    FreeBodyKinematics(model, data, q);
    return;
  }
  for (int i = 0; i < model.num_bodies(); ++i) {
    const Body& body = model.bodies[i];
    JointTransform(body.joint, q(i), &data.X_parent[i]);
    data.X_world[i] =
        body.parent == kBase ? data.X_parent[i] : data.X_world[body.parent] * data.X_parent[i];
  }
}

}  // namespace mbstream

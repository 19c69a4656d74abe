#include "server/kinematics/point_jacobian.h"

#include "common/check.h"

namespace mbstream {

void PointJacobian(const Model& model, const Data& data, int frame, Eigen::Ref<Eigen::MatrixXd> J) {
  MBSTREAM_CHECK(frame >= 0 && frame < static_cast<int>(model.frames.size()));
  MBSTREAM_CHECK(J.rows() == 6 && J.cols() == model.num_dofs());
  J.setZero();
  const Vector3d& p = data.frame_world[frame].p;
  for (int j = model.frames[frame].body; j != kBase; j = model.bodies[j].parent) {
    const Joint& joint = model.bodies[j].joint;
    const Vector3d axis = data.X_world[j].R * joint.axis;
    if (joint.type == JointType::kRevolute) {
      J.col(j).head<3>() = axis;
      J.col(j).tail<3>() = axis.cross(p - data.X_world[j].p);
    } else {
      J.col(j).tail<3>() = axis;
    }
  }
}

}  // namespace mbstream

#include "server/kinematics/point_jacobian.h"

#include "shared/common/check.h"

namespace mbstream {

void PointJacobian(const Model& model, const Data& data, int frame, Eigen::Ref<Eigen::MatrixXd> J) {
  MBSTREAM_CHECK(frame >= 0 && frame < static_cast<int>(model.frames.size()));
  MBSTREAM_CHECK(J.rows() == 6 && J.cols() == model.num_dofs());
  J.setZero();
  const Vector3d& p = data.frame_world[frame].p;
  for (int j = model.frames[frame].body; j != kBase; j = model.bodies[j].parent) {
    const Body& body = model.bodies[j];
    const Joint& joint = body.joint;
    const int col = model.has_quaternions() ? body.v_index : j;  // equal when built
    if (joint.type == JointType::kBall) {                        // w_B (model.h)
      const Matrix3d& R = data.X_world[j].R;
      const Vector3d r = p - data.X_world[j].p;
      for (int k = 0; k < 3; ++k) {
        J.col(col + k).head<3>() = R.col(k);
        J.col(col + k).tail<3>() = R.col(k).cross(r);
      }
      continue;
    }
    if (joint.type == JointType::kFree) {  // [v_WB; w_B] (model.h)
      const Matrix3d& R = data.X_world[j].R;
      const Vector3d r = p - data.X_world[j].p;
      for (int k = 0; k < 3; ++k) {
        J(3 + k, col + k) = 1.0;
        J.col(col + 3 + k).head<3>() = R.col(k);
        J.col(col + 3 + k).tail<3>() = R.col(k).cross(r);
      }
      continue;
    }
    const Vector3d axis = data.X_world[j].R * joint.axis;
    if (joint.type == JointType::kRevolute) {
      J.col(col).head<3>() = axis;
      J.col(col).tail<3>() = axis.cross(p - data.X_world[j].p);
    } else {
      J.col(col).tail<3>() = axis;
    }
  }
}

}  // namespace mbstream

#include "server/contact/point_forces.h"

#include "server/contact/contact_bodies.h"

namespace mbstream {

namespace {

int Column(const Model& model, int j) {
  return model.has_quaternions() ? model.bodies[j].v_index : j;
}

}  // namespace

Vector3d PointVelocity(const Model& model, const Data& data, int body, const Vector3d& p,
                       const Eigen::VectorXd& qd) {
  Vector3d v = Vector3d::Zero();
  for (int j = body; j != kBase; j = model.bodies[j].parent) {
    const Joint& joint = model.bodies[j].joint;
    const int col = Column(model, j);
    const Vector3d r = p - data.X_world[j].p;
    if (joint.type == JointType::kBall) {  // w_B (model.h)
      v += (data.X_world[j].R * Vector3d(qd(col), qd(col + 1), qd(col + 2))).cross(r);
      continue;
    }
    if (joint.type == JointType::kFree) {  // [v_WB; w_B] (model.h)
      const Matrix3d& R = data.X_world[j].R;
      v += Vector3d(qd(col), qd(col + 1), qd(col + 2)) +
           (R * Vector3d(qd(col + 3), qd(col + 4), qd(col + 5))).cross(r);
      continue;
    }
    const Vector3d axis = data.X_world[j].R * joint.axis;
    v += (joint.type == JointType::kRevolute ? axis.cross(r) : axis) * qd(col);
  }
  return v;
}

void AddPointForce(const Model& model, const Data& data, int body, const Vector3d& p,
                   const Vector3d& f, Eigen::VectorXd* tau) {
  for (int j = body; j != kBase; j = model.bodies[j].parent) {
    const Joint& joint = model.bodies[j].joint;
    const int col = Column(model, j);
    const Vector3d r = p - data.X_world[j].p;
    if (joint.type == JointType::kBall) {  // the moment about the centre in the child frame
      const Vector3d moment_B = data.X_world[j].R.transpose() * r.cross(f);
      for (int k = 0; k < 3; ++k) (*tau)(col + k) += moment_B(k);
      continue;
    }
    if (joint.type == JointType::kFree) {  // the force in the world, the moment in the body
      const Vector3d moment_B = data.X_world[j].R.transpose() * r.cross(f);
      for (int k = 0; k < 3; ++k) {
        (*tau)(col + k) += f(k);
        (*tau)(col + 3 + k) += moment_B(k);
      }
      continue;
    }
    const Vector3d axis = data.X_world[j].R * joint.axis;
    (*tau)(col) += joint.type == JointType::kRevolute ? axis.dot(r.cross(f)) : axis.dot(f);
  }
}

Vector3d JointContactBodies::PointVelocity(int body, const Vector3d& p) const {
  return mbstream::PointVelocity(model_, data_, body, p, *qd_);
}

void JointContactBodies::AddPointForce(int body, const Vector3d& p, const Vector3d& f) {
  mbstream::AddPointForce(model_, data_, body, p, f, tau_);
}

}  // namespace mbstream

#include "server/model/model.h"

#include <Eigen/Geometry>

namespace mbstream {

int Model::FindFrame(const std::string& frame_name) const {
  for (size_t i = 0; i < frames.size(); ++i) {
    if (frames[i].name == frame_name) return static_cast<int>(i);
  }
  return -1;
}

int Model::FindBody(const std::string& body_name) const {
  for (size_t i = 0; i < bodies.size(); ++i) {
    if (bodies[i].name == body_name) return static_cast<int>(i);
  }
  return -1;
}

int Model::BodyOfVelocity(int v) const {
  if (!has_quaternions()) return v;
  for (size_t i = bodies.size(); i-- > 0;) {
    if (bodies[i].v_index <= v) return static_cast<int>(i);
  }
  return -1;
}

double Model::TotalMass() const {
  double m = 0.0;
  for (const Body& b : bodies) m += b.inertia.mass;
  return m;
}

void IndexCoordinates(Model* model) {
  model->free_bodies.clear();
  model->ball_bodies.clear();
  model->quaternions.clear();
  int q = 0, v = 0;
  for (size_t i = 0; i < model->bodies.size(); ++i) {
    Body& body = model->bodies[i];
    body.q_index = q;
    body.v_index = v;
    if (body.free()) {
      model->free_bodies.push_back(static_cast<int>(i));
      model->quaternions.push_back(q + 3);
    } else if (body.ball()) {
      model->ball_bodies.push_back(static_cast<int>(i));
      model->quaternions.push_back(q);
    }
    q += body.nq();
    v += body.nv();
  }
}

void NeutralPositions(const Model& model, double* q) {
  for (int i = 0; i < model.nq(); ++i) q[i] = 0.0;
  for (const int i : model.ball_bodies) q[model.bodies[i].q_index] = 1.0;
  for (const int i : model.free_bodies) {
    const Body& body = model.bodies[i];
    double* qi = q + body.q_index;
    Eigen::Quaterniond quat(body.X_W0.R);
    quat.normalize();
    if (quat.w() < 0.0) quat.coeffs() = -quat.coeffs();  // the same rotation, qw >= 0
    qi[0] = body.X_W0.p.x();
    qi[1] = body.X_W0.p.y();
    qi[2] = body.X_W0.p.z();
    qi[3] = quat.w();
    qi[4] = quat.x();
    qi[5] = quat.y();
    qi[6] = quat.z();
  }
}

}  // namespace mbstream

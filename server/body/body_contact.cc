#include "server/body/body_contact.h"

#include "server/body/body_mechanics.h"

namespace mbstream {

BodyContact::BodyContact(const BodyMechanics& mechanics, ContactForces& forces)
    : mechanics_(mechanics), forces_(forces), X_(static_cast<size_t>(mechanics.model().n)) {}

void BodyContact::LoadPoses() {
  const BodyModel& bm = mechanics_.model();
  for (int i = 0; i < bm.n; ++i) {
    X_[i].R = mechanics_.R(i);
    X_[i].p = mechanics_.x(i) - X_[i].R * bm.com[i];
  }
}

bool BodyContact::AddTo(Eigen::VectorXd* f) {
  LoadPoses();
  f_ = f;
  power_ = 0.0;
  const bool finite = forces_.AddForces(*this);
  f_ = nullptr;
  return finite;
}

void BodyContact::Distances(double* g) {
  LoadPoses();
  forces_.SignedDistances(*this, g);
}

Vector3d BodyContact::PointVelocity(int body, const Vector3d& p) const {
  if (body == kBase) return Vector3d::Zero();
  const Vector3d r = p - mechanics_.x(body);
  return mechanics_.v(body) + (mechanics_.R(body) * mechanics_.w(body)).cross(r);
}

void BodyContact::AddPointForce(int body, const Vector3d& p, const Vector3d& f) {
  if (body == kBase) return;
  const Vector3d r = p - mechanics_.x(body);
  f_->segment<3>(6 * body) += f;
  f_->segment<3>(6 * body + 3) += mechanics_.R(body).transpose() * r.cross(f);
  power_ += f.dot(PointVelocity(body, p));
}

}  // namespace mbstream

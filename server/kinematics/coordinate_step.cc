#include "server/kinematics/coordinate_step.h"

#include <cmath>

#include "server/kinematics/quaternion.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

// quat <- quat (x) exp(dw / 2), renormalised: the rotation turned by the rotation vector dw
// in its own (rotated) frame.
void TurnQuaternion(const double* dw, double scale, double* quat) {
  const double x = scale * dw[0], y = scale * dw[1], z = scale * dw[2];
  const double angle = std::sqrt(x * x + y * y + z * z);
  // sin(a/2) / a, continued to a = 0 by its series.
  const double s = angle > 1e-8 ? std::sin(0.5 * angle) / angle : 0.5 - angle * angle / 48.0;
  const double c = std::cos(0.5 * angle);
  const double e[4] = {c, s * x, s * y, s * z};
  const double w0 = quat[0], x0 = quat[1], y0 = quat[2], z0 = quat[3];
  quat[0] = w0 * e[0] - x0 * e[1] - y0 * e[2] - z0 * e[3];
  quat[1] = w0 * e[1] + x0 * e[0] + y0 * e[3] - z0 * e[2];
  quat[2] = w0 * e[2] - x0 * e[3] + y0 * e[0] + z0 * e[1];
  quat[3] = w0 * e[3] + x0 * e[2] - y0 * e[1] + z0 * e[0];
  quaternion::Normalise(quat);
}

}  // namespace

void StepPositions(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& dv, double scale,
                   Eigen::Ref<Eigen::VectorXd> q) {
  MBSTREAM_CHECK(dv.size() == model.nv() && q.size() == model.nq());
  if (!model.has_quaternions()) {
    q += scale * dv;
    return;
  }
  for (const Body& body : model.bodies) {
    const int iq = body.q_index, iv = body.v_index;
    if (body.free()) {
      for (int k = 0; k < 3; ++k) q(iq + k) += scale * dv(iv + k);
      TurnQuaternion(dv.data() + iv + 3, scale, q.data() + iq + 3);
    } else if (body.ball()) {
      TurnQuaternion(dv.data() + iv, scale, q.data() + iq);
    } else {
      q(iq) += scale * dv(iv);
    }
  }
}

std::vector<int> PositionOfVelocity(const Model& model) {
  std::vector<int> q_of_v(static_cast<size_t>(model.nv()), -1);
  for (const Body& body : model.bodies) {
    if (body.nv() == 1) q_of_v[static_cast<size_t>(body.v_index)] = body.q_index;
  }
  return q_of_v;
}

void NormaliseQuaternions(const Model& model, Eigen::Ref<Eigen::VectorXd> q) {
  for (const int k : model.quaternions) quaternion::Normalise(q.data() + k);
}

}  // namespace mbstream

#include "server/dynamics/aba.h"

#include "server/dynamics/aba_passes.h"
#include "server/dynamics/free_tree.h"
#include "shared/common/check.h"

namespace mbstream {

using aba_passes::AccelerationPass;
using aba_passes::BackwardPass;

const Eigen::VectorXd& Aba(const Model& model, Data& data,
                           const Eigen::Ref<const Eigen::VectorXd>& q,
                           const Eigen::Ref<const Eigen::VectorXd>& qd,
                           const Eigen::Ref<const Eigen::VectorXd>& tau) {
  if (model.has_quaternions()) {
    MBSTREAM_CHECK(q.size() == model.nq() && qd.size() == model.nv() && tau.size() == model.nv());
    return free_tree::Aba(model, data, q, qd, tau);
  }
  const int n = model.num_bodies();
  MBSTREAM_CHECK(q.size() == n && qd.size() == n && tau.size() == n);
  aba_passes::ForwardPasses(model, q, qd, data);
  for (int i = n - 1; i >= 0; --i) {
    const Body& body = model.bodies[i];
    aba_passes::DispatchStep(
        body.joint,
        [&](auto K, auto L) { aba_passes::BackwardPassAboutAxis<K(), L()>(body, i, tau(i), data); },
        [&](auto shape) { BackwardPass<shape()>(body, i, tau(i), data); });
  }
  Vector6d a_base = Vector6d::Zero();
  a_base.tail<3>() = -model.gravity;  // gravity as an upward acceleration of the base
  for (int i = 0; i < n; ++i) {
    const Body& body = model.bodies[i];
    const Vector6d& a_parent = body.parent == kBase ? a_base : data.a[body.parent];
    aba_passes::DispatchStep(
        body.joint,
        [&](auto K, auto L) { aba_passes::AccelerationPassAboutAxis<K(), L()>(a_parent, i, data); },
        [&](auto shape) { AccelerationPass<shape()>(a_parent, i, data); });
  }
  return data.qdd;
}

}  // namespace mbstream

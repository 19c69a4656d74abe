#include "server/model/ball_joint.h"

#include <cmath>
#include <numbers>

#include "server/model/model.h"
#include "shared/common/format.h"

namespace mbstream {

namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

std::string LockMessage(const BallJoint& ball, const std::string& when, double y) {
  const char* name = ball.name.c_str();
  return FormatString(
      "ball joint '%s' (%s) reached its gimbal lock %s (%s.y = %.2f deg; the lock is at +-90 "
      "deg, where its three axes %s.x, %s.y, %s.z, Cardan angles x-y-z, cannot follow the "
      "motion: the child's z axis lines up with the joint frame's x axis); turn the joint's "
      "frame in the model file so that the motion keeps those two axes apart",
      name, ball.where.c_str(), when.c_str(), name, y * kDeg, name, name, name);
}

// The index in q of the ball joint's middle (y) angle.
int MiddleAngle(const Model& model, const BallJoint& ball) {
  const int body = ball.first_body + 1;
  return model.has_free_bodies() ? model.bodies[body].q_index : body;
}

}  // namespace

std::optional<std::string> GimbalLockMessage(const Model& model, const double* q, double t,
                                             double margin) {
  for (const BallJoint& ball : model.ball_joints) {
    const double y = q[MiddleAngle(model, ball)];
    if (std::abs(std::cos(y)) <= std::sin(margin)) {
      return LockMessage(ball, FormatString("at t = %g s", t), y);
    }
  }
  return std::nullopt;
}

GimbalWatch::GimbalWatch(const Model& model)
    : model_(model), last_cos_(model.ball_joints.size(), 1.0) {}

std::optional<std::string> GimbalWatch::Check(const double* q, double t) {
  std::optional<std::string> message = GimbalLockMessage(model_, q, t);
  for (size_t b = 0; b < model_.ball_joints.size() && !message; ++b) {
    const BallJoint& ball = model_.ball_joints[b];
    const double c = std::cos(q[MiddleAngle(model_, ball)]);
    if (!first_ && (c > 0.0) != (last_cos_[b] > 0.0)) {
      message = LockMessage(ball, FormatString("between t = %g s and t = %g s", last_t_, t),
                            q[MiddleAngle(model_, ball)]);
    }
  }
  for (size_t b = 0; b < model_.ball_joints.size(); ++b) {
    const double y = q[MiddleAngle(model_, model_.ball_joints[b])];
    last_cos_[b] = std::cos(y);
    if (std::abs(last_cos_[b]) < closest_) {
      closest_ = std::abs(last_cos_[b]);
      closest_ball_ = b;
      closest_t_ = t;
      closest_y_ = y;
    }
  }
  last_t_ = t;
  first_ = false;
  return message;
}

std::optional<std::string> GimbalWatch::NearWarning() const {
  if (!(closest_ < std::sin(kGimbalWarningRad))) return std::nullopt;
  const BallJoint& ball = model_.ball_joints[closest_ball_];
  const char* name = ball.name.c_str();
  return FormatString(
      "ball joint '%s' (%s) came within %.1f deg of its gimbal lock at t = %g s (%s.y = %.2f "
      "deg): near it the rates of %s.x and %s.z grow as 1/cos(%s.y) and the integrator's steps "
      "shrink; turn the joint's frame in the model file to keep the motion away from it",
      name, ball.where.c_str(), std::asin(closest_) * kDeg, closest_t_, name, closest_y_ * kDeg,
      name, name, name);
}

}  // namespace mbstream

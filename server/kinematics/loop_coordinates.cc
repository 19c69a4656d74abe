#include "server/kinematics/loop_coordinates.h"

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "server/kinematics/forward_kinematics.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

int Columns(LoopJointType type) {
  switch (type) {
    case LoopJointType::kRevolute:
    case LoopJointType::kPrismatic:
      return 1;
    case LoopJointType::kBall:
      return 3;
    case LoopJointType::kFixed:
    case LoopJointType::kMimic:  // the follower is a tree joint, in the tree's columns
      return 0;
  }
  return 0;
}

// A unit vector perpendicular to unit `a`.
Vector3d Perpendicular(const Vector3d& a) {
  const Vector3d other = std::abs(a.x()) < 0.9 ? Vector3d::UnitX() : Vector3d::UnitY();
  return a.cross(other).normalized();
}

}  // namespace

std::vector<std::string> LoopCoordinateNames(const std::vector<LoopClosure>& loops) {
  std::vector<std::string> names;
  for (const LoopClosure& loop : loops) {
    if (loop.type == LoopJointType::kBall) {
      for (const char* axis : {".x", ".y", ".z"}) names.push_back(loop.name + axis);
    } else if (Columns(loop.type) == 1) {
      names.push_back(loop.name);
    }
  }
  return names;
}

LoopCoordinates::LoopCoordinates(const Model& model, const std::vector<LoopClosure>& loops)
    : model_(model),
      loops_(loops),
      data_(model),
      w_(static_cast<size_t>(model.num_bodies()), Vector3d::Zero()),
      v_(static_cast<size_t>(model.num_bodies()), Vector3d::Zero()),
      last_angle_(loops.size(), 0.0) {
  for (const LoopClosure& loop : loops) size_ += Columns(loop.type);
}

void LoopCoordinates::Velocities(const Eigen::VectorXd& qd) {
  const Vector3d zero = Vector3d::Zero();
  for (int i = 0; i < model_.num_bodies(); ++i) {
    const Body& body = model_.bodies[i];
    const int c = body.v_index;
    if (body.free()) {  // v_WB in the world, w_B in the body
      v_[i] = qd.segment<3>(c);
      w_[i] = data_.X_world[i].R * qd.segment<3>(c + 3);
      continue;
    }
    const int p = body.parent;
    const Vector3d& wp = p == kBase ? zero : w_[p];
    const Vector3d& vp = p == kBase ? zero : v_[p];
    const Vector3d& op = p == kBase ? zero : data_.X_world[p].p;
    const Vector3d uq = body.ball() ? Vector3d(data_.X_world[i].R * qd.segment<3>(c))
                                    : Vector3d(data_.X_world[i].R * body.joint.axis * qd(c));
    v_[i] = vp + wp.cross(data_.X_world[i].p - op);
    w_[i] = wp;
    if (body.joint.type != JointType::kPrismatic) {
      w_[i] += uq;
    } else {
      v_[i] += uq;
    }
  }
}

void LoopCoordinates::Compute(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                              Eigen::VectorXd* value, Eigen::VectorXd* rate) {
  MBSTREAM_CHECK(value->size() == size_ && rate->size() == size_);
  BodyKinematics(model_, data_, q);
  Velocities(qd);
  const Vector3d zero = Vector3d::Zero();
  // A side's frame J in the world, its angular velocity and its origin's velocity.
  const auto side = [&](int body, const Pose& X_J, Matrix3d* R, Vector3d* p, Vector3d* w,
                        Vector3d* v) {
    if (body == kBase) {
      *R = X_J.R;
      *p = X_J.p;
      *w = *v = zero;
      return;
    }
    const Pose& X_W = data_.X_world[body];
    *R = X_W.R * X_J.R;
    *p = X_W.Apply(X_J.p);
    *w = w_[body];
    *v = v_[body] + w_[body].cross(*p - X_W.p);
  };
  int k = 0;
  for (size_t l = 0; l < loops_.size(); ++l) {
    const LoopClosure& loop = loops_[l];
    if (Columns(loop.type) == 0) continue;
    Matrix3d Ra, Rb;
    Vector3d pa, pb, wa, wb, va, vb;
    side(loop.body_a, loop.X_AJ, &Ra, &pa, &wa, &va);
    side(loop.body_b, loop.X_BJ, &Rb, &pb, &wb, &vb);
    const Matrix3d R_AB = Ra.transpose() * Rb;
    const Vector3d w_rel = Ra.transpose() * (wb - wa);
    switch (loop.type) {
      case LoopJointType::kRevolute: {
        const Vector3d u = Perpendicular(loop.axis);
        const Vector3d turned = R_AB * u;
        double angle = std::atan2(loop.axis.dot(u.cross(turned)), u.dot(turned));
        if (!first_) {  // continue from the previous angle
          const double turns = std::round((last_angle_[l] - angle) / (2.0 * std::numbers::pi));
          angle += 2.0 * std::numbers::pi * turns;
        }
        last_angle_[l] = angle;
        (*value)(k) = angle;
        (*rate)(k) = loop.axis.dot(w_rel);
        ++k;
        break;
      }
      case LoopJointType::kPrismatic: {
        const Vector3d d = pb - pa;
        (*value)(k) = loop.axis.dot(Ra.transpose() * d);
        (*rate)(k) = loop.axis.dot(Ra.transpose() * (vb - va - wa.cross(d)));
        ++k;
        break;
      }
      case LoopJointType::kBall: {
        const Eigen::AngleAxisd turn(R_AB);
        value->segment<3>(k) = turn.angle() * turn.axis();
        rate->segment<3>(k) = w_rel;
        k += 3;
        break;
      }
      case LoopJointType::kFixed:
      case LoopJointType::kMimic:
        break;
    }
  }
  first_ = false;
}

}  // namespace mbstream

// Test models with free bodies and ball joints, and random states for them (unit quaternions).
#pragma once

#include <random>
#include <string>

#include <Eigen/Core>

#include "server/kinematics/quaternion.h"
#include "server/model/model_builder.h"

namespace mbstream::testing {

// A body of `mass` (kg) with principal inertias 0.1, 0.2, 0.25 kg*m^2 about its origin.
inline RigidInertia Box(double mass) {
  RigidInertia inertia;
  inertia.mass = mass;
  inertia.inertia_com = Vector3d(0.1, 0.2, 0.25).asDiagonal();
  return inertia;
}

inline RigidInertia RandomInertia(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  RigidInertia inertia;
  inertia.mass = 1.0 + 0.5 * unit(rng);
  inertia.com = 0.1 * Vector3d(unit(rng), unit(rng), unit(rng));
  const Vector3d d(0.03 + 0.005 * unit(rng), 0.035 + 0.005 * unit(rng), 0.04 + 0.005 * unit(rng));
  const Matrix3d R =
      AxisAngleRotation(Vector3d(unit(rng), unit(rng), unit(rng)).normalized(), 3.0 * unit(rng));
  inertia.inertia_com = R * d.asDiagonal() * R.transpose();
  return inertia;
}

// A world of: a fixed-base arm (two revolute joints), a free "torso" with a tree of revolute
// and prismatic joints (rotated origins and general axes among them), a fixed link on it, and
// a lone free "box". Every joint with rotor inertia `armature` (kg*m^2 or kg).
inline Model FloatingTree(std::mt19937& rng, double armature = 0.01) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  ModelBuilder builder("floating", "world");
  auto joint = [&](const std::string& name, JointType type, const Vector3d& axis) {
    Joint j;
    j.name = name;
    j.type = type;
    j.axis = axis.normalized();
    j.X_PJ.p = 0.3 * Vector3d(unit(rng), unit(rng), unit(rng));
    j.X_PJ.R = AxisAngleRotation(Vector3d(unit(rng), unit(rng), unit(rng)).normalized(), unit(rng));
    j.armature = armature;
    return j;
  };
  builder.AddMovingLink("arm1", "world", joint("a1", JointType::kRevolute, Vector3d::UnitZ()),
                        RandomInertia(rng));
  Pose X_W0;
  X_W0.p = Vector3d(0.5, -0.2, 1.0);
  builder.AddFreeLink("torso", "root", X_W0, RandomInertia(rng));
  builder.AddMovingLink("arm2", "arm1", joint("a2", JointType::kRevolute, Vector3d::UnitY()),
                        RandomInertia(rng));
  builder.AddMovingLink("thigh_l", "torso",
                        joint("hip_l", JointType::kRevolute, Vector3d(1, 2, 0.5)),
                        RandomInertia(rng));
  builder.AddMovingLink("shin_l", "thigh_l",
                        joint("knee_l", JointType::kRevolute, Vector3d::UnitX()),
                        RandomInertia(rng));
  builder.AddMovingLink("thigh_r", "torso",
                        joint("hip_r", JointType::kPrismatic, Vector3d(0, 1, 1)),
                        RandomInertia(rng));
  builder.AddFixedLink("foot_r", "thigh_r", Pose{Matrix3d::Identity(), Vector3d(0, 0, -0.2)},
                       RandomInertia(rng));
  builder.AddMovingLink("shin_r", "foot_r",
                        joint("ankle_r", JointType::kRevolute, Vector3d::UnitZ()),
                        RandomInertia(rng));
  builder.AddFreeLink("box", "box", Pose::Identity(), RandomInertia(rng));
  builder.AddPoint("tip", "shin_l", Vector3d(0.1, 0.2, -0.3));
  return builder.Build();
}

// Ball joints in trees: a fixed-base chain world -ball-> b1 -ball-> b2 -revolute-> b3 -ball->
// b4 (a point "tip" on it), and a free "torso" carrying a ball-jointed "upper" whose prismatic
// "slider" carries a ball-jointed "hand". Joint frames rotated and offset at random.
inline Model BallTree(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  auto frame = [&] {
    Pose X;
    X.p = 0.3 * Vector3d(unit(rng), unit(rng), unit(rng));
    X.R = AxisAngleRotation(Vector3d(unit(rng), unit(rng), unit(rng)).normalized(), unit(rng));
    return X;
  };
  auto joint = [&](const std::string& name, JointType type, const Vector3d& axis) {
    Joint j;
    j.name = name;
    j.type = type;
    j.axis = axis.normalized();
    j.X_PJ = frame();
    return j;
  };
  ModelBuilder builder("balls", "world");
  builder.AddBallLink("b1", "world", "ball1", frame(), RandomInertia(rng));
  builder.AddBallLink("b2", "b1", "ball2", frame(), RandomInertia(rng));
  builder.AddMovingLink("b3", "b2", joint("elbow", JointType::kRevolute, Vector3d(1, 0.5, 0.2)),
                        RandomInertia(rng));
  builder.AddBallLink("b4", "b3", "ball4", frame(), RandomInertia(rng));
  builder.AddPoint("tip", "b4", Vector3d(0.1, -0.2, 0.3));
  Pose X_W0;
  X_W0.p = Vector3d(0.5, -0.2, 1.0);
  builder.AddFreeLink("torso", "root", X_W0, RandomInertia(rng));
  builder.AddBallLink("upper", "torso", "shoulder", frame(), RandomInertia(rng));
  builder.AddMovingLink("slider", "upper", joint("slide", JointType::kPrismatic, Vector3d(0, 1, 1)),
                        RandomInertia(rng));
  builder.AddBallLink("hand", "slider", "wrist", frame(), RandomInertia(rng));
  return builder.Build();
}

// Random positions (every quaternion unit: the free bodies' and the ball joints') and random
// velocities.
inline Eigen::VectorXd RandomPositions(const Model& model, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Eigen::VectorXd q(model.nq());
  for (int k = 0; k < q.size(); ++k) q(k) = 2.0 * unit(rng);
  for (const int k : model.quaternions) quaternion::Normalise(&q(k));
  return q;
}

inline Eigen::VectorXd RandomVelocities(const Model& model, std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Eigen::VectorXd v(model.nv());
  for (int k = 0; k < v.size(); ++k) v(k) = scale * unit(rng);
  return v;
}

}  // namespace mbstream::testing

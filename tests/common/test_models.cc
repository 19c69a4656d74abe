#include "tests/common/test_models.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "server/model/model_builder.h"

namespace mbstream::testing {

namespace {

Joint MakeJoint(const char* name, JointType type, const Vector3d& xyz, const Vector3d& axis) {
  Joint joint;
  joint.name = name;
  joint.type = type;
  joint.X_PJ.p = xyz;
  joint.axis = axis.normalized();
  return joint;
}

RigidInertia Box(double m, const Vector3d& com, const Vector3d& size) {
  const double x = size.x(), y = size.y(), z = size.z();
  RigidInertia inertia{m, com, Matrix3d::Zero()};
  inertia.inertia_com.diagonal() << m * (y * y + z * z) / 12, m * (x * x + z * z) / 12,
      m * (x * x + y * y) / 12;
  return inertia;
}

}  // namespace

Model SevenJointArm() {
  ModelBuilder b("seven", "base");
  const Vector3d X = Vector3d::UnitX(), Y = Vector3d::UnitY(), Z = Vector3d::UnitZ();
  const Vector3d axes[7] = {Z, Y, Z, Y, Z, Y, X};
  const double masses[7] = {12, 9, 7, 5, 3, 1.5, 0.4};
  const double lengths[7] = {0.3, 0.45, 0.1, 0.4, 0.1, 0.2, 0.05};
  std::string parent = "base";
  for (int i = 0; i < 7; ++i) {
    const std::string link = "l" + std::to_string(i + 1);
    const std::string joint = "j" + std::to_string(i + 1);
    const double along = i == 0 ? 0.0 : lengths[i - 1];
    b.AddMovingLink(
        link, parent, MakeJoint(joint.c_str(), JointType::kRevolute, {0, 0, along}, axes[i]),
        Box(masses[i], {0.01 * i, 0, 0.5 * lengths[i]}, {0.08, 0.08, std::max(0.05, lengths[i])}));
    parent = link;
  }
  b.AddPoint("tcp", parent, {0.1, 0, 0});
  b.SetTcp("tcp");
  return b.Build();
}

Model Irb1600Model() {
  ModelBuilder b("irb1600", "base_link");
  const Vector3d X = Vector3d::UnitX(), Y = Vector3d::UnitY(), Z = Vector3d::UnitZ();
  b.AddMovingLink("link1", "base_link", MakeJoint("joint1", JointType::kRevolute, {0, 0, 0}, Z),
                  Box(70, {0.05, 0, 0.3}, {0.4, 0.4, 0.5}));
  b.AddMovingLink("link2", "link1",
                  MakeJoint("joint2", JointType::kRevolute, {0.150, 0, 0.4865}, Y),
                  Box(55, {0, 0, 0.24}, {0.15, 0.2, 0.6}));
  b.AddMovingLink("link3", "link2", MakeJoint("joint3", JointType::kRevolute, {0, 0, 0.475}, Y),
                  Box(45, {0.15, 0, 0.02}, {0.4, 0.2, 0.2}));
  b.AddMovingLink("link4", "link3", MakeJoint("joint4", JointType::kRevolute, {0.600, 0, 0}, X),
                  Box(30, {-0.25, 0, 0}, {0.45, 0.12, 0.12}));
  b.AddMovingLink("link5", "link4", MakeJoint("joint5", JointType::kRevolute, {0, 0, 0}, Y),
                  Box(8, {0.02, 0, 0}, {0.1, 0.08, 0.08}));
  b.AddMovingLink("link6", "link5", MakeJoint("joint6", JointType::kRevolute, {0, 0, 0}, X),
                  Box(2, {0.04, 0, 0}, {0.04, 0.06, 0.06}));
  b.AddPoint("tcp", "link6", {0.065, 0, 0});
  b.SetTcp("tcp");
  return b.Build();
}

Model BranchingModel() {
  ModelBuilder b("branching", "base");
  Joint j1 = MakeJoint("j1", JointType::kRevolute, {0.1, 0.0, 0.3}, {0.2, 0.3, 1.0});
  j1.X_PJ.R = Eigen::AngleAxisd(0.3, Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  j1.armature = 0.05;
  b.AddMovingLink("trunk", "base", j1, Box(5, {0.1, 0.0, 0.2}, {0.2, 0.3, 0.5}));
  Joint j2 = MakeJoint("j2", JointType::kPrismatic, {0.0, 0.2, 0.4}, {1.0, -0.5, 0.2});
  j2.armature = 0.5;
  b.AddMovingLink("slider", "trunk", j2, Box(2, {0.0, 0.05, 0.0}, {0.1, 0.1, 0.3}));
  Joint j3 = MakeJoint("j3", JointType::kRevolute, {0.0, -0.2, 0.4}, {0.0, 1.0, 0.3});
  j3.X_PJ.R = Eigen::AngleAxisd(-0.7, Vector3d(0, 1, 1).normalized()).toRotationMatrix();
  b.AddMovingLink("left_arm", "trunk", j3, Box(3, {0.2, 0.0, 0.0}, {0.4, 0.1, 0.1}));
  Pose X_fixed;
  X_fixed.p = {0.4, 0.0, 0.0};
  X_fixed.R = Eigen::AngleAxisd(0.5, Vector3d::UnitZ()).toRotationMatrix();
  b.AddFixedLink("left_hand", "left_arm", X_fixed, Box(1, {0.05, 0, 0}, {0.1, 0.1, 0.1}));
  Joint j4 = MakeJoint("j4", JointType::kRevolute, {0.1, 0.0, 0.0}, {1.0, 0.0, 0.0});
  b.AddMovingLink("finger", "left_hand", j4, Box(0.5, {0.0, 0.0, 0.05}, {0.02, 0.02, 0.1}));
  Joint j5 = MakeJoint("j5", JointType::kRevolute, {0.0, 0.0, 0.2}, {0.0, 0.0, 1.0});
  j5.damping = 0.1;
  b.AddMovingLink("head", "slider", j5, Box(1.5, {0.0, 0.0, 0.1}, {0.2, 0.2, 0.2}));
  b.AddPoint("fingertip", "finger", {0.0, 0.0, 0.1});
  b.SetTcp("fingertip");
  return b.Build();
}

Model SinglePendulum(double m, double l, double i_cm) {
  ModelBuilder b("pendulum", "world");
  RigidInertia bob{m, {0, 0, -l}, Matrix3d::Identity() * i_cm};
  b.AddMovingLink("bob", "world", MakeJoint("pivot", JointType::kRevolute, {0, 0, 0}, {0, 1, 0}),
                  bob);
  return b.Build();
}

Eigen::VectorXd RandomVector(std::mt19937& rng, int n, double scale) {
  std::uniform_real_distribution<double> dist(-scale, scale);
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v(i) = dist(rng);
  return v;
}

}  // namespace mbstream::testing

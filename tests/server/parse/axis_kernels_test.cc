// The dynamics kernels specialised for revolute joints about a coordinate axis
// (server/dynamics/axis_joint_steps.h) give the general path's results to 1e-12 relative, on
// every shipped URDF: each model is run twice, as imported (the specialised steps wherever
// a joint has that shape) and with every joint forced onto the general path (its derived
// shape fields cleared, so JointShape is kGeneralJoint and the full-pose code runs).
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "server/dynamics/aba.h"
#include "server/dynamics/hybrid_dynamics.h"
#include "server/dynamics/rnea.h"
#include "server/kinematics/joint_spatial_transform.h"
#include "server/parse/urdf_import.h"

namespace mbstream {
namespace {

constexpr double kRelative = 1e-12;

// The same mechanism with every joint on the general path.
Model OnGeneralPath(Model model) {
  for (Body& body : model.bodies) {
    body.joint.axis_index = -1;
    body.joint.origin_rotation_identity = false;
    body.joint.axis_kernel = -1;
  }
  return model;
}

Eigen::VectorXd Random(std::mt19937& rng, int n, double scale) {
  std::uniform_real_distribution<double> dist(-scale, scale);
  Eigen::VectorXd x(n);
  for (int i = 0; i < n; ++i) x(i) = dist(rng);
  return x;
}

// |x - expected| <= kRelative |expected| (Euclidean norms), with a failure message naming what.
::testing::AssertionResult Close(const char* what, const Eigen::VectorXd& x,
                                 const Eigen::VectorXd& expected) {
  const double error = (x - expected).norm();
  if (error <= kRelative * expected.norm()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << what << ": |difference| " << error << " > 1e-12 * " << expected.norm();
}

class AxisKernelsTest : public ::testing::TestWithParam<const char*> {
 protected:
  AxisKernelsTest()
      : model_(ImportUrdfFile(std::string(MBSTREAM_SOURCE_DIR) + "/models/" + GetParam()).model),
        general_(OnGeneralPath(model_)),
        data_(model_),
        general_data_(general_) {}

  Model model_, general_;
  Data data_, general_data_;
};

TEST_P(AxisKernelsTest, ModelHasAxisJointsAndTheGeneralCopyHasNone) {
  int axis_joints = 0;
  for (int i = 0; i < model_.num_dofs(); ++i) {
    if (JointShape(model_.bodies[i].joint) >= 0) ++axis_joints;
    EXPECT_EQ(JointShape(general_.bodies[i].joint), kGeneralJoint);
    EXPECT_EQ(general_.bodies[i].joint.axis_kernel, -1);
  }
  EXPECT_GT(axis_joints, 0) << "the specialised steps would not be exercised";
}

TEST_P(AxisKernelsTest, InverseDynamicsMatchesTheGeneralPath) {
  std::mt19937 rng(11);
  const int n = model_.num_dofs();
  for (int trial = 0; trial < 50; ++trial) {
    // Angles up to 20 rad: several turns, every quadrant of the joints' (cos, sin).
    const Eigen::VectorXd q = Random(rng, n, 20.0), qd = Random(rng, n, 3.0),
                          qdd = Random(rng, n, 10.0);
    const Eigen::VectorXd expected = Rnea(general_, general_data_, q, qd, qdd);
    ASSERT_TRUE(Close("tau", Rnea(model_, data_, q, qd, qdd), expected));
    for (int i = 0; i < n; ++i) {  // the bodies' velocities, which consistent_init reads
      ASSERT_TRUE(Close("v", data_.v[i], general_data_.v[i])) << "body " << i;
      ASSERT_TRUE(Close("a", data_.a[i], general_data_.a[i])) << "body " << i;
    }
    ASSERT_TRUE(Close("h", NonlinearEffects(model_, data_, q, qd),
                      NonlinearEffects(general_, general_data_, q, qd)));
    ASSERT_TRUE(
        Close("g", GravityVector(model_, data_, q), GravityVector(general_, general_data_, q)));
  }
}

TEST_P(AxisKernelsTest, ForwardAndHybridDynamicsMatchTheGeneralPath) {
  std::mt19937 rng(12);
  const int n = model_.num_dofs();
  std::vector<unsigned char> prescribed(n, 0);
  for (int i = 0; i < n; i += 3) prescribed[i] = 1;
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::VectorXd q = Random(rng, n, 20.0), qd = Random(rng, n, 3.0),
                          tau = Random(rng, n, 50.0), qdd = Random(rng, n, 10.0);
    const Eigen::VectorXd expected = Aba(general_, general_data_, q, qd, tau);
    ASSERT_TRUE(Close("qdd", Aba(model_, data_, q, qd, tau), expected));
    const Eigen::VectorXd expected_hybrid =
        HybridAba(general_, general_data_, q, qd, tau, qdd, prescribed);
    ASSERT_TRUE(Close("hybrid qdd", HybridAba(model_, data_, q, qd, tau, qdd, prescribed),
                      expected_hybrid));
    ASSERT_TRUE(Close("hybrid tau", data_.tau, general_data_.tau));
  }
}

TEST_P(AxisKernelsTest, RotorInertiaMatchesTheGeneralPath) {
  // The shipped URDFs have none: give every joint some (kg*m^2 or kg).
  Model model = model_;
  for (int i = 0; i < model.num_dofs(); ++i) model.bodies[i].joint.armature = 0.01 * (i + 1);
  const Model general = OnGeneralPath(model);
  Data data(model), general_data(general);
  std::mt19937 rng(13);
  const int n = model.num_dofs();
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd q = Random(rng, n, 20.0), qd = Random(rng, n, 3.0),
                          x = Random(rng, n, 10.0);
    ASSERT_TRUE(Close("tau", Rnea(model, data, q, qd, x), Rnea(general, general_data, q, qd, x)));
    ASSERT_TRUE(Close("qdd", Aba(model, data, q, qd, x), Aba(general, general_data, q, qd, x)));
  }
}

// A branching tree with a joint of every kernel (axis K x offset shape: on x, y, z, zero,
// anywhere), mixed with prismatic and rotated-origin joints (the general path, so that the
// upper-triangle articulated inertias meet a parent that reads all of its matrix).
Model EveryKernelTree(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const Vector3d offsets[5] = {
      {0.3, 0, 0}, {0, -0.2, 0}, {0, 0, 0.25}, {0, 0, 0}, {0.1, -0.2, 0.3}};
  Model model;
  auto add = [&](JointType type, const Vector3d& axis, const Vector3d& offset, bool rotated) {
    Body body;
    const int index = model.num_dofs();
    body.name = "b" + std::to_string(index);
    body.parent = index == 0 ? kBase : (index - 1) / 2;  // two children per body
    body.joint.type = type;
    body.joint.axis = axis;
    body.joint.X_PJ.p = offset;
    if (rotated) body.joint.X_PJ.R = AxisAngleRotation(Vector3d(1, 2, -1).normalized(), 0.7);
    DeriveJointShape(body.joint);
    body.inertia.mass = 1.0 + unit(rng) * 0.5;
    body.inertia.com = Vector3d(unit(rng), unit(rng), unit(rng)) * 0.1;
    const Matrix3d a = Matrix3d::Random();
    body.inertia.inertia_com = 0.01 * (a * a.transpose() + Matrix3d::Identity());
    model.bodies.push_back(body);
  };
  for (int k = 0; k < 3; ++k) {
    for (const Vector3d& offset : offsets) {
      add(JointType::kRevolute, Vector3d::Unit(k), offset, false);
    }
    add(JointType::kPrismatic, Vector3d::Unit(k), offsets[4], false);
    add(JointType::kRevolute, Vector3d::Unit(k), offsets[k], true);
  }
  return model;
}

TEST(AxisKernelsEveryShapeTest, ForwardAndHybridDynamicsMatchTheGeneralPath) {
  std::mt19937 rng(14);
  Model model = EveryKernelTree(rng);
  std::vector<bool> kernel_seen(15, false);
  for (const Body& body : model.bodies) {
    if (body.joint.axis_kernel >= 0) kernel_seen[body.joint.axis_kernel] = true;
  }
  for (int kernel = 0; kernel < 15; ++kernel) EXPECT_TRUE(kernel_seen[kernel]) << kernel;
  const int n = model.num_dofs();
  std::vector<unsigned char> prescribed(n, 0);
  for (int i = 0; i < n; i += 4) prescribed[i] = 1;
  for (double armature : {0.0, 0.02}) {  // 0: the move's folded zeros; else the full projection
    for (Body& body : model.bodies) body.joint.armature = armature;
    const Model general = OnGeneralPath(model);
    Data data(model), general_data(general);
    for (int trial = 0; trial < 50; ++trial) {
      const Eigen::VectorXd q = Random(rng, n, 20.0), qd = Random(rng, n, 3.0),
                            tau = Random(rng, n, 5.0), qdd = Random(rng, n, 10.0);
      ASSERT_TRUE(
          Close("qdd", Aba(model, data, q, qd, tau), Aba(general, general_data, q, qd, tau)))
          << "armature " << armature;
      ASSERT_TRUE(Close("hybrid qdd", HybridAba(model, data, q, qd, tau, qdd, prescribed),
                        HybridAba(general, general_data, q, qd, tau, qdd, prescribed)));
      ASSERT_TRUE(Close("hybrid tau", data.tau, general_data.tau));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(ShippedUrdfs, AxisKernelsTest,
                         ::testing::Values("irb1600/irb1600.urdf", "big/tree38.urdf",
                                           "big/chain100.urdf", "pendulum/single_pendulum.urdf",
                                           "pendulum/double_pendulum.urdf"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string name = info.param;
                           name = name.substr(name.find('/') + 1);
                           return name.substr(0, name.find('.'));
                         });

}  // namespace
}  // namespace mbstream

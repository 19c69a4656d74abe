// Forward kinematics against the seed's sample points; the Jacobian against finite
// differences of forward kinematics.
#include "server/kinematics/forward_kinematics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "server/kinematics/point_jacobian.h"
#include "tests/common/seed_kinematics.h"
#include "tests/common/test_models.h"

namespace mbstream {
namespace {

using std::numbers::pi;

Vector3d Tcp(const Model& model, Data& data, const Eigen::VectorXd& q) {
  ForwardKinematics(model, data, q);
  return FramePosition(data, model.tcp_frame);
}

Vector3d SeedTcp(const Eigen::VectorXd& q) { return testing::SeedTcp(q.data()); }

TEST(KinematicsTest, Irb1600ZeroPoseMatchesSeed) {
  const Model model = testing::Irb1600Model();
  Data data(model);
  const Vector3d tcp = Tcp(model, data, Eigen::VectorXd::Zero(6));
  EXPECT_NEAR(tcp.x(), 0.815, 1e-12);
  EXPECT_NEAR(tcp.y(), 0.0, 1e-12);
  EXPECT_NEAR(tcp.z(), 0.9615, 1e-12);
}

TEST(KinematicsTest, Irb1600SamplePoseMatchesSeed) {
  const Model model = testing::Irb1600Model();
  Data data(model);
  Eigen::VectorXd q(6);
  q << pi, pi / 3, pi / 4, pi, 0.6 * pi, pi;
  const Vector3d tcp = Tcp(model, data, q);
  // The seed prints 9 decimals: compare to them, and to the closed form to 1e-12 m.
  EXPECT_NEAR(tcp.x(), -0.470981559, 5e-10);
  EXPECT_NEAR(tcp.y(), 0.0, 1e-12);
  EXPECT_NEAR(tcp.z(), 0.147846341, 5e-10);
  EXPECT_LT((tcp - SeedTcp(q)).norm(), 1e-12);
}

TEST(KinematicsTest, Irb1600MatchesClosedFormOnRandomPoses) {
  const Model model = testing::Irb1600Model();
  Data data(model);
  std::mt19937 rng(7);
  for (int k = 0; k < 100; ++k) {
    const Eigen::VectorXd q = testing::RandomVector(rng, 6, pi);
    EXPECT_LT((Tcp(model, data, q) - SeedTcp(q)).norm(), 1e-12);
  }
}

// Central differences of FK: linear velocity of the point and angular velocity from the
// rotation's change, per unit joint velocity.
Eigen::MatrixXd FiniteDifferenceJacobian(const Model& model, int frame, const Eigen::VectorXd& q) {
  Data data(model);
  const int n = model.num_dofs();
  const double h = 1e-6;
  Eigen::MatrixXd J(6, n);
  ForwardKinematics(model, data, q);
  const Matrix3d R0 = data.frame_world[frame].R;
  for (int j = 0; j < n; ++j) {
    Eigen::VectorXd qp = q, qm = q;
    qp(j) += h;
    qm(j) -= h;
    ForwardKinematics(model, data, qp);
    const Pose Xp = data.frame_world[frame];
    ForwardKinematics(model, data, qm);
    const Pose Xm = data.frame_world[frame];
    const Matrix3d dR = (Xp.R - Xm.R) / (2 * h);
    const Matrix3d W = dR * R0.transpose();  // [w]x = dR/dt R^T (w in the base frame)
    J.col(j) << W(2, 1), W(0, 2), W(1, 0), (Xp.p - Xm.p) / (2 * h);
  }
  return J;
}

TEST(KinematicsTest, JacobianMatchesFiniteDifferences) {
  for (const Model& model : {testing::Irb1600Model(), testing::BranchingModel()}) {
    Data data(model);
    std::mt19937 rng(11);
    for (int k = 0; k < 10; ++k) {
      const Eigen::VectorXd q = testing::RandomVector(rng, model.num_dofs(), 2.0);
      ForwardKinematics(model, data, q);
      for (int frame = 0; frame < static_cast<int>(model.frames.size()); ++frame) {
        PointJacobian(model, data, frame, data.J);
        const Eigen::MatrixXd fd = FiniteDifferenceJacobian(model, frame, q);
        EXPECT_LT((data.J - fd).cwiseAbs().maxCoeff(), 1e-7)
            << model.name << " frame " << model.frames[frame].name;
      }
    }
  }
}

TEST(KinematicsTest, FixedLinksAndBranchesArePlaced) {
  const Model model = testing::BranchingModel();
  Data data(model);
  ForwardKinematics(model, data, Eigen::VectorXd::Zero(model.num_dofs()));
  // At q = 0 the joints do not move: the fingertip is the chain of fixed offsets.
  const Pose& trunk = data.frame_world[model.FindFrame("trunk")];
  const Pose& arm = data.frame_world[model.FindFrame("left_arm")];
  const Pose& hand = data.frame_world[model.FindFrame("left_hand")];
  EXPECT_TRUE(hand.p.isApprox(arm.Apply(Vector3d(0.4, 0, 0)), 1e-14));
  EXPECT_TRUE(trunk.p.isApprox(Vector3d(0.1, 0.0, 0.3), 1e-14));
  EXPECT_EQ(model.num_dofs(), 5);
  EXPECT_EQ(model.bodies[model.FindBody("finger")].parent, model.FindBody("left_arm"));
}

}  // namespace
}  // namespace mbstream

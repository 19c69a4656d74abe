// The dynamics algorithms checked against each other and against closed forms.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>

#include "server/dynamics/aba.h"
#include "server/dynamics/crba.h"
#include "server/dynamics/energy.h"
#include "server/dynamics/rnea.h"
#include "server/kinematics/forward_kinematics.h"
#include "tests/common/test_models.h"

namespace mbstream {
namespace {

class DynamicsTest : public ::testing::TestWithParam<Model (*)()> {
 protected:
  DynamicsTest() : model_(GetParam()()), data_(model_), n_(model_.num_dofs()) {}
  Model model_;
  Data data_;
  int n_;
  std::mt19937 rng_{42};
};

TEST_P(DynamicsTest, AbaAgreesWithCrbaAndCholesky) {
  for (int k = 0; k < 50; ++k) {
    const Eigen::VectorXd q = testing::RandomVector(rng_, n_, 3.0);
    const Eigen::VectorXd qd = testing::RandomVector(rng_, n_, 2.0);
    const Eigen::VectorXd tau = testing::RandomVector(rng_, n_, 50.0);
    const Eigen::VectorXd h = NonlinearEffects(model_, data_, q, qd);
    const Eigen::MatrixXd M = Crba(model_, data_, q);
    const Eigen::VectorXd expected = M.llt().solve(tau - h);
    const Eigen::VectorXd qdd = Aba(model_, data_, q, qd, tau);
    EXPECT_LT((qdd - expected).norm(), 1e-10 * expected.norm()) << "state " << k;
  }
}

TEST_P(DynamicsTest, RneaInvertsAba) {
  for (int k = 0; k < 50; ++k) {
    const Eigen::VectorXd q = testing::RandomVector(rng_, n_, 3.0);
    const Eigen::VectorXd qd = testing::RandomVector(rng_, n_, 2.0);
    const Eigen::VectorXd tau = testing::RandomVector(rng_, n_, 50.0);
    const Eigen::VectorXd qdd = Aba(model_, data_, q, qd, tau);
    const Eigen::VectorXd back = Rnea(model_, data_, q, qd, qdd);
    EXPECT_LT((back - tau).norm(), 1e-10 * tau.norm()) << "state " << k;
  }
}

TEST_P(DynamicsTest, MassMatrixIsSymmetricPositiveDefiniteAndMatchesRnea) {
  for (int k = 0; k < 20; ++k) {
    const Eigen::VectorXd q = testing::RandomVector(rng_, n_, 3.0);
    const Eigen::MatrixXd M = Crba(model_, data_, q);
    EXPECT_LT((M - M.transpose()).cwiseAbs().maxCoeff(), 1e-14 * M.norm());
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(M).eigenvalues().minCoeff(), 0.0);
    // Column j of M is RNEA with unit acceleration j, minus the bias (no velocity).
    const Eigen::VectorXd g = GravityVector(model_, data_, q);
    for (int j = 0; j < n_; ++j) {
      const Eigen::VectorXd e = Eigen::VectorXd::Unit(n_, j);
      const Eigen::VectorXd col = Rnea(model_, data_, q, Eigen::VectorXd::Zero(n_), e) - g;
      EXPECT_LT((col - M.col(j)).norm(), 1e-12 * (1.0 + M.norm()));
    }
  }
}

TEST_P(DynamicsTest, KineticEnergyIsHalfQdMQd) {
  for (int k = 0; k < 20; ++k) {
    const Eigen::VectorXd q = testing::RandomVector(rng_, n_, 3.0);
    const Eigen::VectorXd qd = testing::RandomVector(rng_, n_, 2.0);
    const double expected = 0.5 * qd.dot(Crba(model_, data_, q) * qd);
    EXPECT_NEAR(KineticEnergy(model_, data_, q, qd), expected, 1e-12 * expected);
  }
}

TEST_P(DynamicsTest, GravityVectorIsGradientOfPotentialEnergy) {
  const Eigen::VectorXd q = testing::RandomVector(rng_, n_, 3.0);
  const Eigen::VectorXd g = GravityVector(model_, data_, q);
  const double h = 1e-6;
  for (int j = 0; j < n_; ++j) {
    Eigen::VectorXd qp = q, qm = q;
    qp(j) += h;
    qm(j) -= h;
    ForwardKinematics(model_, data_, qp);
    const double up = PotentialEnergy(model_, data_);
    ForwardKinematics(model_, data_, qm);
    const double down = PotentialEnergy(model_, data_);
    EXPECT_NEAR(g(j), (up - down) / (2 * h), 1e-6 * (1.0 + g.norm())) << "joint " << j;
  }
}

INSTANTIATE_TEST_SUITE_P(Models, DynamicsTest,
                         ::testing::Values(&testing::Irb1600Model, &testing::BranchingModel),
                         [](const auto& info) {
                           return info.index == 0 ? "Irb1600" : "Branching";
                         });

TEST(PendulumTest, AccelerationEqualsClosedForm) {
  const double m = 2.0, l = 0.7, i_cm = 0.01, g = 9.81;
  const Model model = testing::SinglePendulum(m, l, i_cm);
  Data data(model);
  for (double angle : {0.0, 0.3, -1.2, 2.5}) {
    Eigen::VectorXd q(1), qd(1), tau(1);
    q << angle;
    qd << 1.7;  // a single revolute joint has no velocity-dependent force
    tau << 0.0;
    const double expected = -m * g * l * std::sin(angle) / (i_cm + m * l * l);
    EXPECT_NEAR(Aba(model, data, q, qd, tau)(0), expected, 1e-13);
  }
}

TEST(ArmatureTest, AddsToTheDiagonalOnly) {
  const Model model = testing::BranchingModel();
  Model bare = model;
  for (Body& body : bare.bodies) body.joint.armature = 0.0;
  Data data(model), bare_data(bare);
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(model.num_dofs(), 0.4);
  const Eigen::MatrixXd diff = Crba(model, data, q) - Crba(bare, bare_data, q);
  for (int i = 0; i < model.num_dofs(); ++i) {
    for (int j = 0; j < model.num_dofs(); ++j) {
      EXPECT_NEAR(diff(i, j), i == j ? model.bodies[i].joint.armature : 0.0, 1e-14);
    }
  }
}

}  // namespace
}  // namespace mbstream

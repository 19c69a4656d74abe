// The dynamics algorithms checked against each other and against closed forms.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <vector>

#include "server/dynamics/aba.h"
#include "server/dynamics/crba.h"
#include "server/dynamics/energy.h"
#include "server/dynamics/hybrid_dynamics.h"
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

// Hybrid dynamics against the partitioned system it replaces in the joint-space ODE: with
// the prescribed joints' accelerations given, M_ff qdd_f = tau_f - RNEA(q, qd, [qdd_p; 0])_f
// and the prescribed joints' forces RNEA(q, qd, qdd)_p.
TEST_P(DynamicsTest, HybridAbaAgreesWithPartitionedCrbaAndRnea) {
  for (int k = 0; k < 50; ++k) {
    std::vector<unsigned char> prescribed(n_);
    for (int i = 0; i < n_; ++i) prescribed[i] = (i + k) % 3 == 0 ? 1 : 0;
    const Eigen::VectorXd q = testing::RandomVector(rng_, n_, 3.0);
    const Eigen::VectorXd qd = testing::RandomVector(rng_, n_, 2.0);
    const Eigen::VectorXd tau = testing::RandomVector(rng_, n_, 50.0);
    Eigen::VectorXd qdd_given = testing::RandomVector(rng_, n_, 5.0);
    Eigen::VectorXd biased = qdd_given;
    std::vector<int> free;
    for (int i = 0; i < n_; ++i) {
      if (!prescribed[i]) {
        free.push_back(i);
        biased(i) = 0.0;
      }
    }
    const Eigen::VectorXd bias = Rnea(model_, data_, q, qd, biased);
    const Eigen::MatrixXd M = Crba(model_, data_, q);
    const int nf = static_cast<int>(free.size());
    Eigen::MatrixXd M_ff(nf, nf);
    Eigen::VectorXd rhs(nf);
    for (int a = 0; a < nf; ++a) {
      rhs(a) = tau(free[a]) - bias(free[a]);
      for (int b = 0; b < nf; ++b) M_ff(a, b) = M(free[a], free[b]);
    }
    const Eigen::VectorXd qdd_free = M_ff.llt().solve(rhs);
    Eigen::VectorXd expected = qdd_given;
    for (int a = 0; a < nf; ++a) expected(free[a]) = qdd_free(a);
    const Eigen::VectorXd forces = Rnea(model_, data_, q, qd, expected);

    const Eigen::VectorXd qdd = HybridAba(model_, data_, q, qd, tau, qdd_given, prescribed);
    EXPECT_LT((qdd - expected).norm(), 1e-10 * expected.norm()) << "state " << k;
    for (int i = 0; i < n_; ++i) {
      if (prescribed[i]) {
        EXPECT_EQ(qdd(i), qdd_given(i));
        EXPECT_NEAR(data_.tau(i), forces(i), 1e-10 * forces.norm()) << "joint " << i;
      }
    }
  }
}

TEST_P(DynamicsTest, HybridAbaWithNothingPrescribedIsAbaBitForBit) {
  const std::vector<unsigned char> none(n_, 0);
  for (int k = 0; k < 10; ++k) {
    const Eigen::VectorXd q = testing::RandomVector(rng_, n_, 3.0);
    const Eigen::VectorXd qd = testing::RandomVector(rng_, n_, 2.0);
    const Eigen::VectorXd tau = testing::RandomVector(rng_, n_, 50.0);
    const Eigen::VectorXd aba = Aba(model_, data_, q, qd, tau);
    const Eigen::VectorXd hybrid = HybridAba(model_, data_, q, qd, tau, data_.zeros, none);
    for (int i = 0; i < n_; ++i) EXPECT_EQ(aba(i), hybrid(i));
  }
}

TEST_P(DynamicsTest, HybridAbaWithEverythingPrescribedIsRnea) {
  const std::vector<unsigned char> all(n_, 1);
  for (int k = 0; k < 10; ++k) {
    const Eigen::VectorXd q = testing::RandomVector(rng_, n_, 3.0);
    const Eigen::VectorXd qd = testing::RandomVector(rng_, n_, 2.0);
    const Eigen::VectorXd qdd = testing::RandomVector(rng_, n_, 5.0);
    const Eigen::VectorXd rnea = Rnea(model_, data_, q, qd, qdd);
    HybridAba(model_, data_, q, qd, data_.zeros, qdd, all);
    EXPECT_LT((data_.tau - rnea).norm(), 1e-12 * rnea.norm());
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

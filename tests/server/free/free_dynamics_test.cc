// The algorithms with free bodies and ball joints against each other (ABA against CRBA + RNEA,
// hybrid dynamics against ABA, the energy against the mass matrix), the point Jacobian against
// differences of forward kinematics, and a lone free body against the Newton-Euler equations.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "server/contact/point_forces.h"
#include "server/dynamics/aba.h"
#include "server/dynamics/crba.h"
#include "server/dynamics/energy.h"
#include "server/dynamics/hybrid_dynamics.h"
#include "server/dynamics/rnea.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/kinematics/free_joint.h"
#include "server/kinematics/point_jacobian.h"
#include "tests/server/free/free_tree_model.h"

namespace mbstream {
namespace {

using testing::BallTree;
using testing::FloatingTree;
using testing::RandomPositions;
using testing::RandomVelocities;

double Relative(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).norm() / std::max(1.0, b.norm());
}

void ExpectAbaSolvesTheMassMatrixEquation(const Model& model, std::mt19937& rng) {
  Data data(model);
  double worst = 0.0;
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::VectorXd q = RandomPositions(model, rng);
    const Eigen::VectorXd qd = RandomVelocities(model, rng, 2.0);
    const Eigen::VectorXd tau = RandomVelocities(model, rng, 5.0);
    const Eigen::VectorXd qdd = Aba(model, data, q, qd, tau);
    const Eigen::MatrixXd M = Crba(model, data, q);
    EXPECT_LT((M - M.transpose()).norm(), 1e-14 * M.norm());
    const Eigen::VectorXd h = NonlinearEffects(model, data, q, qd);
    worst = std::max(worst, Relative(M * qdd + h, tau));
    // And RNEA of ABA's accelerations gives the forces back.
    worst = std::max(worst, Relative(Rnea(model, data, q, qd, qdd), tau));
    // Kinetic energy = qd^T M qd / 2.
    const double T = KineticEnergy(model, data, q, qd);
    EXPECT_NEAR(T, 0.5 * qd.dot(M * qd), 1e-12 * T);
  }
  EXPECT_LT(worst, 1e-12);
}

TEST(FreeDynamicsTest, AbaSolvesTheMassMatrixEquation) {
  std::mt19937 rng(3);
  const Model model = FloatingTree(rng);
  ASSERT_EQ(model.nq(), 6 + 14);
  ASSERT_EQ(model.nv(), 6 + 12);
  ExpectAbaSolvesTheMassMatrixEquation(model, rng);
}

TEST(FreeDynamicsTest, AbaSolvesTheMassMatrixEquationWithBallJoints) {
  std::mt19937 rng(31);
  ExpectAbaSolvesTheMassMatrixEquation(BallTree(rng), rng);
}

void ExpectHybridDynamicsMatchesAba(const Model& model, std::mt19937& rng) {
  Data data(model);
  std::vector<unsigned char> prescribed(model.nv(), 0);
  for (const Body& body : model.bodies) {
    if (body.nv() == 1 && body.v_index % 2 == 0) prescribed[body.v_index] = 1;
  }
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd q = RandomPositions(model, rng);
    const Eigen::VectorXd qd = RandomVelocities(model, rng, 2.0);
    const Eigen::VectorXd tau = RandomVelocities(model, rng, 5.0);
    const Eigen::VectorXd qdd = Aba(model, data, q, qd, tau);
    // Prescribing ABA's own accelerations gives ABA's other accelerations and the given forces.
    const Eigen::VectorXd hybrid = HybridAba(model, data, q, qd, tau, qdd, prescribed);
    EXPECT_LT(Relative(hybrid, qdd), 1e-12);
    for (int v = 0; v < model.nv(); ++v) {
      if (prescribed[v]) {
        EXPECT_NEAR(data.tau(v), tau(v), 1e-10 * (1.0 + std::abs(tau(v))));
      }
    }
  }
}

TEST(FreeDynamicsTest, HybridDynamicsMatchesAba) {
  std::mt19937 rng(4);
  ExpectHybridDynamicsMatchesAba(FloatingTree(rng), rng);
}

TEST(FreeDynamicsTest, HybridDynamicsMatchesAbaWithBallJoints) {
  std::mt19937 rng(41);
  ExpectHybridDynamicsMatchesAba(BallTree(rng), rng);
}

// q' = G(q) qd of every joint (free_joint.h, ball_joint.h), into rate (nq values).
void PositionRates(const Model& model, const double* q, const double* qd, double* rate) {
  for (const Body& body : model.bodies) {
    if (body.free()) {
      free_joint::PositionRate(q + body.q_index, qd + body.v_index, rate + body.q_index);
    } else if (body.ball()) {
      quaternion::Rate(q + body.q_index, qd + body.v_index, rate + body.q_index);
    } else {
      rate[body.q_index] = qd[body.v_index];
    }
  }
}

void ExpectPointJacobianMatchesDifferencesOfKinematics(const Model& model, std::mt19937& rng) {
  Data data(model);
  const int tip = model.FindFrame("tip");
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::VectorXd q = RandomPositions(model, rng);
    const Eigen::VectorXd qd = RandomVelocities(model, rng, 1.0);
    ForwardKinematics(model, data, q);
    Eigen::MatrixXd J(6, model.nv());
    PointJacobian(model, data, tip, J);
    const Vector6d twist = J * qd;
    // q(+-h) by q' = G(q) qd, to second order in h (central differences).
    const double h = 1e-6;
    auto step = [&](double dt) {
      Eigen::VectorXd rate(model.nq());
      PositionRates(model, q.data(), qd.data(), rate.data());
      const Eigen::VectorXd half = q + 0.5 * dt * rate;
      PositionRates(model, half.data(), qd.data(), rate.data());  // midpoint
      const Eigen::VectorXd moved = q + dt * rate;
      ForwardKinematics(model, data, moved);
      return data.frame_world[tip];
    };
    const Pose plus = step(h), minus = step(-h);
    const Vector3d velocity = (plus.p - minus.p) / (2 * h);
    const Matrix3d dR = (plus.R - minus.R) / (2 * h);
    ForwardKinematics(model, data, q);
    const Matrix3d W = dR * data.frame_world[tip].R.transpose();  // [w]x
    const Vector3d w(W(2, 1), W(0, 2), W(1, 0));
    EXPECT_LT((twist.head<3>() - w).norm(), 1e-7);
    EXPECT_LT((twist.tail<3>() - velocity).norm(), 1e-7);
  }
}

TEST(FreeDynamicsTest, PointJacobianMatchesDifferencesOfKinematics) {
  std::mt19937 rng(5);
  ExpectPointJacobianMatchesDifferencesOfKinematics(FloatingTree(rng), rng);
}

TEST(FreeDynamicsTest, PointJacobianMatchesDifferencesOfKinematicsWithBallJoints) {
  std::mt19937 rng(51);
  ExpectPointJacobianMatchesDifferencesOfKinematics(BallTree(rng), rng);
}

// Contact's point velocity and generalised force (server/contact/point_forces.h, walked up the
// chain without J) against the point Jacobian's linear rows: v = J qd, tau = J^T f.
TEST(FreeDynamicsTest, ContactPointForcesAreThePointJacobiansWithBallJoints) {
  std::mt19937 rng(61);
  for (const Model& model : {BallTree(rng), FloatingTree(rng)}) {
    Data data(model);
    const int tip = model.FindFrame("tip");
    const int body = model.frames[tip].body;
    for (int trial = 0; trial < 10; ++trial) {
      const Eigen::VectorXd q = RandomPositions(model, rng);
      const Eigen::VectorXd qd = RandomVelocities(model, rng, 1.0);
      ForwardKinematics(model, data, q);
      Eigen::MatrixXd J(6, model.nv());
      PointJacobian(model, data, tip, J);
      const Vector3d p = data.frame_world[tip].p;
      const Vector3d f = RandomVelocities(model, rng, 3.0).head<3>();
      Eigen::VectorXd tau = Eigen::VectorXd::Zero(model.nv());
      AddPointForce(model, data, body, p, f, &tau);
      const Eigen::VectorXd expected = J.bottomRows<3>().transpose() * f;
      EXPECT_LT((tau - expected).norm(), 1e-13 * (1.0 + expected.norm()));
      const Vector3d v = J.bottomRows<3>() * qd;
      EXPECT_LT((PointVelocity(model, data, body, p, qd) - v).norm(), 1e-13 * (1.0 + v.norm()));
    }
  }
}

TEST(FreeDynamicsTest, ALoneFreeBodyFollowsNewtonAndEuler) {
  std::mt19937 rng(6);
  ModelBuilder builder("body", "world");
  const RigidInertia inertia = testing::RandomInertia(rng);
  builder.AddFreeLink("b", "b", Pose::Identity(), inertia);
  const Model model = builder.Build();
  Data data(model);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::VectorXd q = RandomPositions(model, rng);
    const Eigen::VectorXd qd = RandomVelocities(model, rng, 3.0);
    const Eigen::VectorXd tau = RandomVelocities(model, rng, 2.0);  // [f_W; n_B about Bo]
    const Eigen::VectorXd qdd = Aba(model, data, q, qd, tau);
    const Matrix3d R = free_joint::Rotation(&q(3));
    const Vector3d w = qd.tail<3>(), dw = qdd.tail<3>();
    const Vector3d c = inertia.com;
    const double m = inertia.mass;
    // The centre of mass: p_cm = p + R c, so a_cm = a + R (dw x c + w x (w x c)) = g + f / m.
    const Vector3d a_cm = qdd.head<3>() + R * (dw.cross(c) + w.cross(w.cross(c)));
    const Vector3d f = tau.head<3>();
    EXPECT_LT((a_cm - (model.gravity + f / m)).norm(), 1e-12 * (1.0 + a_cm.norm()));
    // Euler about the centre of mass, body frame: I dw + w x I w = n_cm.
    const Vector3d n_cm = tau.tail<3>() - c.cross(R.transpose() * f);
    const Matrix3d& I = inertia.inertia_com;
    EXPECT_LT((I * dw + w.cross(I * w) - n_cm).norm(), 1e-12 * (1.0 + n_cm.norm()));
  }
}

}  // namespace
}  // namespace mbstream

// The body mechanics against finite differences: G is the derivative of g along the
// velocities, gamma the velocity-product part of its second derivative; consistent
// initial states satisfy every constraint.
#include "server/body/body_mechanics.h"

#include <gtest/gtest.h>

#include "server/body/body_cuts.h"
#include "server/body/consistent_init.h"
#include "server/body/quaternion.h"
#include "shared/common/check.h"
#include "tests/common/test_models.h"
#include "tests/server/body/body_test_util.h"

namespace mbstream {
namespace {

// Advances the positions of y by dt along the velocities of y (x += v dt, e rotated by
// w dt in body axes), exactly to first order.
Eigen::VectorXd Move(const BodyModel& bm, const Eigen::VectorXd& y, double dt) {
  Eigen::VectorXd moved = y;
  for (int b = 0; b < bm.n; ++b) {
    moved.segment<3>(BodyModel::position(b)) += dt * y.segment<3>(bm.velocity(b));
    const Vector4d e = y.segment<4>(BodyModel::quaternion(b));
    const Vector3d w = y.segment<3>(bm.omega(b));
    // e (x) exp(w dt / 2), normalised like e.
    const double angle = w.norm() * dt;
    Vector4d step(1, 0, 0, 0);
    if (angle != 0) {
      step(0) = std::cos(angle / 2);
      step.tail<3>() = std::sin(angle / 2) * w.normalized();
    }
    Vector4d product;
    product(0) = e(0) * step(0) - e.tail<3>().dot(step.tail<3>());
    product.tail<3>() =
        e(0) * step.tail<3>() + step(0) * e.tail<3>() + e.tail<3>().cross(step.tail<3>());
    moved.segment<4>(BodyModel::quaternion(b)) = product;
  }
  return moved;
}

// The drives and body model of `model` under `config`, which a BodyMechanics refers to.
struct MechanicsOf {
  MechanicsOf(const Model& model, const RunConfig& config)
      : drives(model, config.drives), bm(MakeBodyModel(model, drives, Eigen::VectorXd())) {}
  BodyMechanics Make() const { return BodyMechanics(bm, drives); }
  DriveSet drives;
  BodyModel bm;
};

struct Evaluated {
  Eigen::VectorXd g, gdot, nu;
};

Evaluated Evaluate(BodyMechanics& mech, double t, const Eigen::VectorXd& y) {
  mech.Load(t, y.data());
  mech.EvaluateConstraints(true);
  return {mech.g(), mech.G() * mech.nu() + mech.g_t(), mech.nu()};
}

// G nu + g_t against central differences of g along the motion, gamma against those of
// G nu + g_t, at random states of `model` under `config`.
void ExpectConstraintDerivatives(const Model& model, const RunConfig& config,
                                 const std::vector<LoopClosure>& loops = {}) {
  MechanicsOf of(model, config);
  AddCutJoints(loops, &of.bm);  // every row kept: none is dropped here
  const BodyModel& bm = of.bm;
  BodyMechanics mech = of.Make();
  std::mt19937 rng(7);
  for (int trial = 0; trial < 3; ++trial) {
    const Eigen::VectorXd y = testing::RandomBodyState(bm, rng);
    const double t = 1.3, dt = 1e-6;
    const Evaluated now = Evaluate(mech, t, y);
    const Eigen::VectorXd gamma = mech.gamma();
    const Evaluated ahead = Evaluate(mech, t + dt, Move(bm, y, dt));
    const Evaluated behind = Evaluate(mech, t - dt, Move(bm, y, -dt));
    const Eigen::VectorXd gdot_fd = (ahead.g - behind.g) / (2 * dt);
    EXPECT_LT((gdot_fd - now.gdot).cwiseAbs().maxCoeff(), 1e-7)
        << "trial " << trial << "\n"
        << (Eigen::MatrixXd(bm.m, 2) << gdot_fd, now.gdot).finished();
    // d/dt (G nu + g_t) with nu held constant is the velocity-product part: -gamma.
    const Eigen::VectorXd gddot_fd = (ahead.gdot - behind.gdot) / (2 * dt);
    EXPECT_LT((gddot_fd + gamma).cwiseAbs().maxCoeff(), 1e-6) << "trial " << trial;
  }
}

TEST(BodyMechanicsTest, ConstraintDerivativesMatchFiniteDifferences) {
  RunConfig config = testing::Scene("seed-servo");
  config.drives[1] = testing::Scene("seed-run").drives[1];  // two prescribed joints
  config.drives[1].velocity_source = false;
  config.drives[4] = config.drives[1];
  ExpectConstraintDerivatives(testing::Irb1600(), config);
}

TEST(BodyMechanicsTest, ConstraintDerivativesOfPrismaticAndBranchingJoints) {
  const Model model = testing::BranchingModel();
  ExpectConstraintDerivatives(model, testing::BranchingDrives(model, /*all_prescribed=*/true));
  ExpectConstraintDerivatives(model, testing::BranchingDrives(model, /*all_prescribed=*/false));
}

TEST(BodyMechanicsTest, ConstraintDerivativesOfCutJoints) {
  const Model model = testing::BranchingModel();
  ExpectConstraintDerivatives(model, testing::BranchingDrives(model, /*all_prescribed=*/false),
                              testing::CutsOfEveryKind());
}

TEST(BodyMechanicsTest, ConsistentInitialStateSatisfiesTheConstraints) {
  const Model& model = testing::Irb1600();
  const RunConfig config = testing::Scene("seed-servo");
  const DriveSet drives(model, config.drives);
  Eigen::VectorXd q0(6), qd0(6);
  q0 << 0.3, -0.4, 0.5, 1.0, -0.7, 2.0;
  qd0 << 0.5, -0.2, 0.3, 1.0, 0.4, -0.9;
  const BodyModel bm = MakeBodyModel(model, drives, q0);
  BodyMechanics mech(bm, drives);
  BodyInitialState init;
  ASSERT_TRUE(ConsistentInitialState(model, bm, mech, 0.0, q0, qd0, &init));
  EXPECT_LT(init.constraint_residual, 1e-12);
  mech.Load(0.0, init.y.data());
  mech.EvaluateConstraints(false);
  mech.EvaluateForces();
  for (int j = 0; j < 6; ++j) {
    EXPECT_NEAR(mech.q()(j), q0(j), 1e-12);
    EXPECT_NEAR(mech.qd()(j), qd0(j), 1e-12);
  }
}

// EvaluateConstraints and EvaluateForces write only the entries of G and M that can be
// non-zero (they no longer clear the matrices): evaluated at one state after another, they
// must give exactly what a fresh BodyMechanics gives at the last state, armature included.
void ExpectReuseEqualsFresh(const Model& model, const RunConfig& config) {
  const MechanicsOf of(model, config);
  BodyMechanics reused = of.Make();
  std::mt19937 rng(11);
  for (int trial = 0; trial < 4; ++trial) {
    const Eigen::VectorXd y = testing::RandomBodyState(of.bm, rng);
    const double t = 0.7 * trial;
    BodyMechanics fresh = of.Make();
    for (BodyMechanics* mech : {&reused, &fresh}) {
      mech->Load(t, y.data());
      mech->EvaluateConstraints(true);
      mech->EvaluateForces();
    }
    // Bit for bit (operator== on the coefficients), not within a tolerance.
    EXPECT_TRUE((reused.G().array() == fresh.G().array()).all()) << "trial " << trial;
    EXPECT_TRUE((reused.M().array() == fresh.M().array()).all()) << "trial " << trial;
    EXPECT_TRUE((reused.f().array() == fresh.f().array()).all()) << "trial " << trial;
    EXPECT_TRUE((reused.g().array() == fresh.g().array()).all()) << "trial " << trial;
    EXPECT_TRUE((reused.gamma().array() == fresh.gamma().array()).all()) << "trial " << trial;
  }
}

TEST(BodyMechanicsTest, ReusedStorageEvaluatesAsFreshStorage) {
  ExpectReuseEqualsFresh(testing::Irb1600(), testing::Scene("seed-servo"));
  const Model model = testing::BranchingModel();  // prismatic joints, armature, branches
  ExpectReuseEqualsFresh(model, testing::BranchingDrives(model, /*all_prescribed=*/true));
  ExpectReuseEqualsFresh(model, testing::BranchingDrives(model, /*all_prescribed=*/false));
}

}  // namespace
}  // namespace mbstream

// The loop constraints against finite differences and the linkages' geometry; the rank of
// planar loops described with spatial joints; the solver's Newton and allocation-free steps.
#include "server/kinematics/loop_constraints.h"

#include <gtest/gtest.h>

#include <random>

#include "server/kinematics/forward_kinematics.h"
#include "server/kinematics/loop_solver.h"
#include "server/parse/sdf_import.h"
#include "tests/common/allocation_counter.h"
#include "tests/common/test_models.h"

namespace mbstream {
namespace {

const std::string kFourBar = std::string(MBSTREAM_SOURCE_DIR) + "/models/linkages/four_bar.sdf";
const std::string kSliderCrank =
    std::string(MBSTREAM_SOURCE_DIR) + "/models/linkages/slider_crank.sdf";

Pose RandomPose(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Pose X;
  X.R = AxisAngleRotation(Vector3d(u(rng), u(rng), u(rng)).normalized(), 2.0 * u(rng));
  X.p = Vector3d(u(rng), u(rng), u(rng)) * 0.3;
  return X;
}

// Cut joints of every type between bodies of a spatial arm (and the base): the equations
// need not hold for their derivatives to be checked.
std::vector<LoopClosure> SpatialLoops(const Model& model, std::mt19937& rng) {
  std::vector<LoopClosure> loops;
  const LoopJointType types[] = {LoopJointType::kRevolute, LoopJointType::kPrismatic,
                                 LoopJointType::kBall, LoopJointType::kFixed};
  const int n = model.num_dofs();
  const int sides[][2] = {{n - 1, 1}, {kBase, n - 1}, {2, n - 2}, {n - 1, kBase}};
  for (int k = 0; k < 4; ++k) {
    LoopClosure loop;
    loop.name = "cut" + std::to_string(k);
    loop.type = types[k];
    loop.body_a = sides[k][0];
    loop.body_b = sides[k][1];
    loop.X_AJ = RandomPose(rng);
    loop.X_BJ = RandomPose(rng);
    loop.axis = Vector3d(0.3, -0.5, 0.8).normalized();
    loops.push_back(loop);
  }
  return loops;
}

TEST(LoopConstraintsTest, RowsPerJointType) {
  const Model model = testing::Irb1600Model();
  std::mt19937 rng(1);
  const std::vector<LoopClosure> loops = SpatialLoops(model, rng);
  const LoopConstraints constraints(model, loops);
  EXPECT_EQ(constraints.num_rows(), 5 + 5 + 3 + 6);
}

TEST(LoopConstraintsTest, JacobianAndBiasMatchFiniteDifferences) {
  const Model model = testing::Irb1600Model();
  std::mt19937 rng(7);
  const std::vector<LoopClosure> loops = SpatialLoops(model, rng);
  LoopConstraints constraints(model, loops);
  const int n = model.num_dofs(), m = constraints.num_rows();
  Data data(model);
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::VectorXd q = testing::RandomVector(rng, n, 1.5);
    const Eigen::VectorXd qd = testing::RandomVector(rng, n, 2.0);
    BodyKinematics(model, data, q);
    Eigen::MatrixXd G(m, n);
    Eigen::VectorXd bias(m);
    constraints.Jacobian(data, G);
    constraints.Bias(data, qd, bias);
    // G by central differences of phi, column by column.
    const double h = 1e-6;
    Eigen::VectorXd plus(m), minus(m);
    for (int j = 0; j < n; ++j) {
      Eigen::VectorXd qp = q, qm = q;
      qp(j) += h;
      qm(j) -= h;
      BodyKinematics(model, data, qp);
      constraints.Residual(data, qp, plus);
      BodyKinematics(model, data, qm);
      constraints.Residual(data, qm, minus);
      const Eigen::VectorXd column = (plus - minus) / (2.0 * h);
      EXPECT_LT((column - G.col(j)).cwiseAbs().maxCoeff(), 1e-8) << "column " << j;
    }
    // bias = dG/dt qd: the change of G qd along q(t) = q + t qd.
    Eigen::MatrixXd Gp(m, n), Gm(m, n);
    BodyKinematics(model, data, q + h * qd);
    constraints.Jacobian(data, Gp);
    BodyKinematics(model, data, q - h * qd);
    constraints.Jacobian(data, Gm);
    const Eigen::VectorXd expected = (Gp - Gm) * qd / (2.0 * h);
    EXPECT_LT((expected - bias).cwiseAbs().maxCoeff(), 1e-7 * (1.0 + expected.norm()));
  }
}

TEST(LoopConstraintsTest, LinkagesAreClosedAsDrawnWithMobilityOne) {
  for (const std::string& path : {kFourBar, kSliderCrank}) {
    const SdfImport sdf = ImportSdfFile(path);
    LoopConstraints constraints(sdf.model, sdf.loops);
    Data data(sdf.model);
    const Eigen::VectorXd q = Eigen::VectorXd::Zero(sdf.model.num_dofs());
    BodyKinematics(sdf.model, data, q);
    Eigen::VectorXd phi(constraints.num_rows());
    constraints.Residual(data, q, phi);
    EXPECT_LT(phi.cwiseAbs().maxCoeff(), 1e-15) << path;
    // A planar loop closed by a spatial revolute joint: 5 equations, 2 independent (the
    // in-plane gaps); the out-of-plane gap and the axes' alignment hold identically.
    LoopSolver solver(sdf.model, constraints, {});
    bool independent = false;
    Eigen::VectorXd q_assembled = q;
    const LoopRank rank = solver.Analyse(data, q_assembled, &independent);
    EXPECT_EQ(rank.equations, 5) << path;
    EXPECT_EQ(rank.rank, 2) << path;
    EXPECT_EQ(rank.mobility, 1) << path;
    EXPECT_TRUE(independent);
  }
}

TEST(LoopSolverTest, NewtonClosesTheFourBarWithTheCrankHeld) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  const Model& model = sdf.model;
  LoopConstraints constraints(model, sdf.loops);
  Data data(model);
  LoopSolver solver(model, constraints, {0});  // crank_joint held
  bool independent = false;
  solver.Analyse(data, Eigen::VectorXd::Zero(3), &independent);
  EXPECT_TRUE(independent);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(3);
  Eigen::VectorXd held = Eigen::VectorXd::Zero(3);
  held(0) = 0.3;
  const int iterations = solver.SolvePositions(data, q, held, 1e-13, 20);
  EXPECT_GT(iterations, 1);
  EXPECT_LT(iterations, 10);
  EXPECT_DOUBLE_EQ(q(0), 0.3);
  EXPECT_LT(solver.residual().cwiseAbs().maxCoeff(), 1e-13);
  // Velocities: the crank's rate held, the loop's velocity constraint met.
  Eigen::VectorXd qd = Eigen::VectorXd::Zero(3), held_qd = Eigen::VectorXd::Zero(3);
  held_qd(0) = 2.0;
  solver.SolveVelocities(data, qd, held_qd);
  EXPECT_DOUBLE_EQ(qd(0), 2.0);
  EXPECT_LT(solver.velocity_residual().cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_GT(std::abs(qd(1)), 0.1);  // the rocker moves with the crank
}

TEST(LoopSolverTest, SolvesWithoutAllocating) {
  const SdfImport sdf = ImportSdfFile(kSliderCrank);
  const Model& model = sdf.model;
  LoopConstraints constraints(model, sdf.loops);
  Data data(model);
  LoopSolver solver(model, constraints, {0});
  bool independent = false;
  Eigen::VectorXd q = Eigen::VectorXd::Zero(3), qd = Eigen::VectorXd::Zero(3),
                  qdd = Eigen::VectorXd::Zero(3), held = Eigen::VectorXd::Zero(3),
                  mu = Eigen::VectorXd::Zero(3);
  solver.Analyse(data, q, &independent);
  held(0) = 0.5;
  const long before = testing::AllocationCount();
  const int iterations = solver.SolvePositions(data, q, held, 1e-13, 20);
  solver.SolveVelocities(data, qd, held);
  solver.SolveAccelerations(data, qd, qdd, held);
  solver.Multipliers(qdd, mu);
  EXPECT_EQ(testing::AllocationCount() - before, 0);
  EXPECT_GT(iterations, 0);
}

}  // namespace
}  // namespace mbstream

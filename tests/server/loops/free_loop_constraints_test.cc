// The loop constraints of a tree with free bodies and ball joints, in velocity space (issue
// 43): G (nv columns) and the bias against differences of phi along q (+) t v (StepPositions,
// the exact motion at constant v: a quaternion turned by exp(t w / 2), a free origin moved by
// t v_WB), cut joints of every type between free bodies, ball-jointed bodies, their children
// and the world; the cut joints' coordinates' rates against differences of their values.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "server/kinematics/coordinate_step.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/kinematics/loop_constraints.h"
#include "server/kinematics/loop_coordinates.h"
#include "server/model/model_builder.h"

namespace mbstream {
namespace {

Pose RandomPose(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Pose X;
  X.R = Eigen::AngleAxisd(2.0 * u(rng), Vector3d(u(rng), u(rng), u(rng)).normalized())
            .toRotationMatrix();
  X.p = Vector3d(u(rng), u(rng), u(rng)) * 0.3;
  return X;
}

RigidInertia Inertia() { return RigidInertia{1.0, Vector3d(0.1, 0.0, 0.05), Matrix3d::Identity()}; }

// A free torso carrying a ball-jointed arm with a revolute hand and a prismatic slide; a
// second free body, a box.
Model Tree(std::mt19937& rng) {
  ModelBuilder builder("tree", "world");
  builder.AddFreeLink("torso", "torso", RandomPose(rng), Inertia());
  builder.AddBallLink("arm", "torso", "shoulder", RandomPose(rng), Inertia());
  Joint wrist;
  wrist.name = "wrist";
  wrist.type = JointType::kRevolute;
  wrist.X_PJ = RandomPose(rng);
  wrist.axis = Vector3d(0.2, 0.9, -0.3).normalized();
  builder.AddMovingLink("hand", "arm", wrist, Inertia());
  Joint slide;
  slide.name = "slide";
  slide.type = JointType::kPrismatic;
  slide.X_PJ = RandomPose(rng);
  slide.axis = Vector3d(-0.5, 0.1, 0.8).normalized();
  builder.AddMovingLink("slider", "torso", slide, Inertia());
  builder.AddFreeLink("box", "box", RandomPose(rng), Inertia());
  return builder.Build();
}

std::vector<LoopClosure> Loops(const Model& model, std::mt19937& rng) {
  const int torso = model.FindBody("torso"), arm = model.FindBody("arm"),
            hand = model.FindBody("hand"), slider = model.FindBody("slider"),
            box = model.FindBody("box");
  const struct {
    LoopJointType type;
    int a, b;
  } cuts[] = {{LoopJointType::kRevolute, hand, kBase}, {LoopJointType::kPrismatic, box, arm},
              {LoopJointType::kBall, torso, box},      {LoopJointType::kFixed, slider, hand},
              {LoopJointType::kRevolute, kBase, box},  {LoopJointType::kRevolute, arm, torso}};
  std::vector<LoopClosure> loops;
  for (const auto& cut : cuts) {
    LoopClosure loop;
    loop.name = "cut" + std::to_string(loops.size());
    loop.type = cut.type;
    loop.body_a = cut.a;
    loop.body_b = cut.b;
    loop.X_AJ = RandomPose(rng);
    loop.X_BJ = RandomPose(rng);
    loop.axis = Vector3d(0.3, -0.5, 0.8).normalized();
    loops.push_back(loop);
  }
  return loops;
}

Eigen::VectorXd RandomPositions(const Model& model, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd q(model.nq());
  for (int i = 0; i < model.nq(); ++i) q(i) = u(rng);
  NormaliseQuaternions(model, q);
  return q;
}

Eigen::VectorXd Along(const Model& model, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                      double t) {
  Eigen::VectorXd moved = q;
  StepPositions(model, v, t, moved);
  return moved;
}

TEST(FreeLoopConstraintsTest, JacobianAndBiasInVelocitySpaceMatchDifferencesOnTheManifold) {
  std::mt19937 rng(43);
  const Model model = Tree(rng);
  ASSERT_EQ(model.nq(), 7 + 4 + 1 + 1 + 7);
  ASSERT_EQ(model.nv(), 6 + 3 + 1 + 1 + 6);
  const std::vector<LoopClosure> loops = Loops(model, rng);
  LoopConstraints constraints(model, loops);
  const int nv = model.nv(), m = constraints.num_rows();
  ASSERT_EQ(m, 5 + 5 + 3 + 6 + 5 + 5);
  Data data(model);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  const auto phi = [&](const Eigen::VectorXd& q) {
    Eigen::VectorXd value(m);
    BodyKinematics(model, data, q);
    constraints.Residual(data, q, value);
    return value;
  };
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::VectorXd q = RandomPositions(model, rng);
    Eigen::VectorXd v(nv);
    for (int i = 0; i < nv; ++i) v(i) = u(rng);
    BodyKinematics(model, data, q);
    Eigen::MatrixXd G(m, nv);
    Eigen::VectorXd bias(m);
    constraints.Jacobian(data, G);
    constraints.Bias(data, v, bias);
    const double h = 1e-6;
    for (int j = 0; j < nv; ++j) {
      const Eigen::VectorXd e = Eigen::VectorXd::Unit(nv, j);
      const Eigen::VectorXd column =
          (phi(Along(model, q, e, h)) - phi(Along(model, q, e, -h))) / (2.0 * h);
      EXPECT_LT((column - G.col(j)).cwiseAbs().maxCoeff(), 1e-8) << "column " << j;
    }
    // phi'' at v' = 0 is the bias: the second difference along q (+) t v.
    const double k = 1e-4;
    const Eigen::VectorXd second =
        (phi(Along(model, q, v, k)) - 2.0 * phi(q) + phi(Along(model, q, v, -k))) / (k * k);
    EXPECT_LT((second - bias).cwiseAbs().maxCoeff(), 1e-5 * (1.0 + bias.norm()));
    // And dG/dt v by differences of G v.
    Eigen::MatrixXd Gp(m, nv), Gm(m, nv);
    BodyKinematics(model, data, Along(model, q, v, h));
    constraints.Jacobian(data, Gp);
    BodyKinematics(model, data, Along(model, q, v, -h));
    constraints.Jacobian(data, Gm);
    const Eigen::VectorXd expected = (Gp - Gm) * v / (2.0 * h);
    EXPECT_LT((expected - bias).cwiseAbs().maxCoeff(), 1e-7 * (1.0 + expected.norm()));
  }
}

// Each cut joint's frames made to coincide at q (the coordinates are 0 there), the rates of
// its coordinates are the derivatives of their values along q (+) t v, ball joints' rotation
// vectors included (at the identity their rate is the relative angular velocity).
TEST(FreeLoopConstraintsTest, CutCoordinatesRatesMatchDifferencesOfTheirValues) {
  std::mt19937 rng(4);
  const Model model = Tree(rng);
  std::vector<LoopClosure> loops = Loops(model, rng);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::VectorXd q = RandomPositions(model, rng);
  Eigen::VectorXd v(model.nv());
  for (int i = 0; i < model.nv(); ++i) v(i) = u(rng);
  Data data(model);
  BodyKinematics(model, data, q);
  for (LoopClosure& loop : loops) {  // B's frame on A's at q
    const Pose X_WA = loop.body_a == kBase ? loop.X_AJ : data.X_world[loop.body_a] * loop.X_AJ;
    loop.X_BJ = loop.body_b == kBase ? X_WA : data.X_world[loop.body_b].Inverse() * X_WA;
  }
  LoopCoordinates coordinates(model, loops);
  const int n = coordinates.size();
  ASSERT_EQ(n, 1 + 1 + 3 + 1 + 1);  // revolute, prismatic, ball (3), fixed (none), 2 revolute
  Eigen::VectorXd value(n), rate(n), plus(n), minus(n), unused(n);
  coordinates.Compute(q, v, &value, &rate);
  EXPECT_LT(value.cwiseAbs().maxCoeff(), 1e-12);
  const double h = 1e-6;
  LoopCoordinates forward(model, loops), backward(model, loops);
  forward.Compute(Along(model, q, v, h), v, &plus, &unused);
  backward.Compute(Along(model, q, v, -h), v, &minus, &unused);
  const Eigen::VectorXd difference = (plus - minus) / (2.0 * h);
  for (int k = 0; k < n; ++k) EXPECT_NEAR(difference(k), rate(k), 1e-7) << k;
  EXPECT_GT(rate.cwiseAbs().minCoeff(), 1e-3);  // every coordinate moves
}

}  // namespace
}  // namespace mbstream
